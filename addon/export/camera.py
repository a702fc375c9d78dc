"""Scene camera -> engine camera parameters (perspective/orthographic, sensor fit,
shift, clipping, depth of field)."""

from ..utils import normalize_frame, matrix_rows


def camera_params(cam_ob, warn, matrix16=None):
    """cam_ob: the evaluated camera object (bpy or stand-in)."""
    cam = cam_ob.data
    m16 = matrix16 if matrix16 is not None else matrix_rows(cam_ob.matrix_world)
    frame, _ = normalize_frame(m16)
    p = {
        "type": "orthographic" if cam.type == "ORTHO" else "perspective",
        "transform": frame,
        "focal_length": float(cam.lens),
        "sensor_width": float(cam.sensor_width),
        "sensor_height": float(cam.sensor_height),
        "sensor_fit": cam.sensor_fit,
        "shift_x": float(cam.shift_x),
        "shift_y": float(cam.shift_y),
        "clip_start": float(cam.clip_start),
        "clip_end": float(cam.clip_end),
    }
    if cam.type == "ORTHO":
        p["ortho_scale"] = float(cam.ortho_scale)
    elif cam.type == "PANO":
        warn("Camera '%s': panoramic cameras not supported yet, rendered as perspective" % cam_ob.name)
    dof = getattr(cam, "dof", None)
    if dof is not None and dof.use_dof and dof.aperture_fstop > 0.0:
        fstop = float(dof.aperture_fstop)
        if cam.type == "ORTHO":
            radius = 1.0 / (2.0 * fstop)
        else:
            radius = float(cam.lens) * 1e-3 / (2.0 * fstop)
        p["aperture_radius"] = radius
        p["focus_distance"] = focus_distance(cam_ob, dof, m16)
        p["blades"] = int(dof.aperture_blades)
        p["blade_rotation"] = float(dof.aperture_rotation)
        if abs(float(getattr(dof, "aperture_ratio", 1.0)) - 1.0) > 1e-6:
            warn("Camera '%s': anamorphic aperture ratio not supported yet" % cam_ob.name)
    return p


def focus_distance(cam_ob, dof, m16):
    fo = getattr(dof, "focus_object", None)
    if fo is None:
        return float(dof.focus_distance)
    # Distance along the camera's view axis (-Z) to the focus object's origin, as Cycles.
    fm = matrix_rows(fo.matrix_world)
    d = [fm[3] - m16[3], fm[7] - m16[7], fm[11] - m16[11]]
    view = [-m16[2], -m16[6], -m16[10]]
    n = (view[0] ** 2 + view[1] ** 2 + view[2] ** 2) ** 0.5 or 1.0
    return abs(sum(a * b for a, b in zip(d, view)) / n)
