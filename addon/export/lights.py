"""Blender lights -> engine light parameters, in Blender's units (docs/scene-format.md).

point/spot/area: `power` in Watts (Light.energy); sun: `strength` in W/m^2.
radius = shadow_soft_size; area sizes include the object's scale (as Cycles does), so the
transform passed on is free of scale.
"""

from .. import shaders_map
from ..utils import normalize_frame, rgb

AREA_SHAPES = {"SQUARE": "square", "RECTANGLE": "rectangle", "DISK": "disk", "ELLIPSE": "ellipse"}


def light_params(light, matrix16, name, warn, view_layer_attribute=None, image_average=None, image_file=None):
    """light: bpy.types.Light (or stand-in); matrix16: row-major world matrix; image_average /
    image_file: shaders_map's image callbacks (an image in the light's node tree)."""
    frame, scale = normalize_frame(matrix16)
    kind = light.type
    p = {"color": rgb(light.color), "transform": frame}
    if kind == "POINT":
        p.update(type="point", power=float(light.energy), radius=float(light.shadow_soft_size))
    elif kind == "SPOT":
        p.update(type="spot", power=float(light.energy), radius=float(light.shadow_soft_size),
                 spot_size=float(light.spot_size), spot_blend=float(light.spot_blend))
        if abs(scale[0] - scale[1]) > 1e-4 * max(scale[0], scale[1], 1e-12):
            warn("Light '%s': non-uniform scale of a spot light ignored" % name)
    elif kind == "SUN":
        p.update(type="sun", strength=float(light.energy), angle=float(light.angle))
    elif kind == "AREA":
        shape = AREA_SHAPES.get(light.shape, "square")
        sx = float(light.size) * scale[0]
        if shape in ("square", "disk"):
            sy = float(light.size) * scale[1]
        else:
            sy = float(light.size_y) * scale[1]
        if shape in ("square", "disk") and abs(sx - sy) > 1e-6 * max(sx, sy, 1e-12):
            shape = "rectangle" if shape == "square" else "ellipse"
        p.update(type="area", power=float(light.energy), shape=shape, size=sx, size_y=sy)
        spread = getattr(light, "spread", None)
        if spread is not None and float(spread) < 3.14159:
            p["spread"] = float(spread)  # radians; Cycles' soft-box slats
        cyc = getattr(light, "cycles", None)
        if cyc is not None and getattr(cyc, "is_portal", False):
            return None
    else:
        warn("Light '%s': light type %s not supported, skipped" % (name, kind))
        return None
    emission, warning = shaders_map.convert_light(light, view_layer_attribute, image_average, image_file)
    if warning:
        warn(warning)
    if emission is not None:
        p["emission"] = emission  # its Emission's colour and strength, which Cycles multiplies in
    return p
