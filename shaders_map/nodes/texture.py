"""Texture nodes: Image, Environment, Sky, Checker, Noise, Gradient, Voronoi, Musgrave, Wave,
Magic, Brick, White Noise.

Lowering makes each an engine texture node (the procedural ones Blender's own patterns);
constant evaluation replaces a texture by its average colour (with a warning).
"""

from ..ir import Expr
from ..registry import maps, evaluates
from ..evaluate import MAGENTA


def _image_props(node, socket, projection="FLAT"):
    image = getattr(node, "image", None)
    props = {
        "output": getattr(socket, "identifier", "Color"),
        "image": image,
        "image_name": getattr(image, "name", None),
        "filepath": getattr(image, "filepath", None),
        "projection": getattr(node, "projection", projection),
        "interpolation": getattr(node, "interpolation", "Linear"),
        "extension": getattr(node, "extension", "REPEAT"),
        "image_user": getattr(node, "image_user", None),  # a sequence's / movie's frame
    }
    cs = getattr(getattr(image, "colorspace_settings", None), "name", None)
    if cs is not None:
        props["colorspace"] = cs
    return props


@maps("ShaderNodeTexImage")
def tex_image(ctx, node, socket):
    return Expr("tex_image", ctx.label(node), {"vector": ctx.input(node, "Vector", default=(0, 0, 0))},
                _image_props(node, socket))


@maps("ShaderNodeTexEnvironment")
def tex_environment(ctx, node, socket):
    return Expr("tex_environment", ctx.label(node),
                {"vector": ctx.input(node, "Vector", default=(0, 0, 0))},
                _image_props(node, socket, "EQUIRECTANGULAR"))


# Blender's Sky Texture: the world lowering hands a Nishita or Preetham sky in the Background to
# the engine (lights/sky_nishita.h, sky_preetham.h); anywhere else it is a constant.
SKY_SETTINGS = ("sun_disc", "sun_size", "sun_intensity", "sun_elevation", "sun_rotation", "altitude",
                "air_density", "dust_density", "ozone_density")


@maps("ShaderNodeTexSky")
def tex_sky(ctx, node, socket):
    props = {k: getattr(node, k) for k in SKY_SETTINGS if hasattr(node, k)}
    props["sky_type"] = getattr(node, "sky_type", "NISHITA")
    if props["sky_type"] == "PREETHAM":
        props["sun_direction"] = [float(x) for x in getattr(node, "sun_direction", (0.0, 0.0, 1.0))]
        props["turbidity"] = float(getattr(node, "turbidity", 2.2))
    return Expr("tex_sky", ctx.label(node), {"vector": ctx.input(node, "Vector", default=(0, 0, 0))}, props)


@evaluates("tex_sky")
def eval_sky(ev, e):
    ev.approx(e, "a %s sky is supported as the World's Background colour only (Nishita, Preetham); here a constant"
              % e.props.get("sky_type", "NISHITA").title())
    return (0.3, 0.4, 0.6)


@evaluates("tex_image", "tex_environment")
def eval_image(ev, e):
    image = e.props.get("image")
    alpha_out = e.props.get("output") == "Alpha"
    if image is None:
        ev.approx(e, "no image assigned")
        return 0.0 if alpha_out else (0.0, 0.0, 0.0)
    avg = None
    if ev.image_average is not None:
        try:
            avg = ev.image_average(image)
        except Exception as exc:  # never let a bad image stop the export
            ev.approx(e, "image '%s' could not be read (%s)" % (e.props.get("image_name"), exc))
            avg = False
    if avg is None:
        ev.approx(e, "image '%s' approximated by grey" % e.props.get("image_name"))
        rgb, alpha = (0.5, 0.5, 0.5), 1.0
    elif avg is False or avg == "missing":
        if avg == "missing":
            ev.approx(e, "image file '%s' not found" % (e.props.get("filepath") or e.props.get("image_name")))
        rgb, alpha = MAGENTA, 1.0
    else:
        rgb, alpha = avg
        what = "environment" if e.op == "tex_environment" else "image"
        ev.approx(e, "%s '%s' approximated by its average colour" % (what, e.props.get("image_name")))
    return float(alpha) if alpha_out else tuple(float(x) for x in rgb)


@maps("ShaderNodeTexChecker")
def tex_checker(ctx, node, socket):
    return Expr("tex_checker", ctx.label(node), {
        "vector": ctx.input(node, "Vector", default=(0, 0, 0)),
        "color1": ctx.input(node, "Color1", default=(0.8, 0.8, 0.8)),
        "color2": ctx.input(node, "Color2", default=(0.2, 0.2, 0.2)),
        "scale": ctx.input(node, "Scale", default=5.0),
    }, {"output": getattr(socket, "identifier", "Color")})


@evaluates("tex_checker")
def eval_checker(ev, e):
    ev.approx(e, "checker texture approximated by its average")
    if e.props.get("output") == "Fac":
        return 0.5
    c1 = ev.color(e.args["color1"])
    c2 = ev.color(e.args["color2"])
    return tuple(0.5 * (a + b) for a, b in zip(c1, c2))


@maps("ShaderNodeTexNoise")
def tex_noise(ctx, node, socket):
    args = {"vector": ctx.input(node, "Vector", default=(0, 0, 0))}
    for key, name, d in (("w", "W", 0.0), ("scale", "Scale", 5.0), ("detail", "Detail", 2.0),
                         ("roughness", "Roughness", 0.5), ("distortion", "Distortion", 0.0)):
        args[key] = ctx.input(node, name, default=d)
    return Expr("tex_noise", ctx.label(node), args, {
        "output": getattr(socket, "identifier", "Fac"),
        "dimensions": getattr(node, "noise_dimensions", "3D")})


@evaluates("tex_noise")
def eval_noise(ev, e):
    ev.approx(e, "noise texture approximated by its average")
    return 0.5 if e.props.get("output") == "Fac" else (0.5, 0.5, 0.5)


# IES Texture: a luminaire's measured profile (engine/src/lights/ies_profile.h). Its text goes
# to the engine inline, from the node's internal Text or its external file read here, so an
# exported scene carries it; a file that cannot be read goes as its path, for the engine to
# name in its warning.
@maps("ShaderNodeTexIES")
def tex_ies(ctx, node, socket):
    return Expr("tex_ies", ctx.label(node), {"vector": ctx.input(node, "Vector", default=(0, 0, 0)),
                                            "strength": ctx.input(node, "Strength", default=1.0)}, _ies_source(node))


def _ies_source(node):
    if getattr(node, "mode", "INTERNAL") != "EXTERNAL":
        text = getattr(node, "ies", None)
        return {"profile": text.as_string() if text is not None else ""}
    path = _absolute_path(getattr(node, "filepath", "") or "")
    try:
        with open(path, encoding="latin-1") as f:  # LM-63 files are ASCII; some carry Latin-1 names
            return {"profile": f.read()}
    except OSError:
        return {"file": path}


def _absolute_path(path):
    """A Blender path ("//" relative to the .blend) as a file-system one. bpy only inside
    Blender (the graph walk needs none of it)."""
    if not path.startswith("//"):
        return path
    try:
        import bpy
    except ImportError:
        return path[2:]
    return bpy.path.abspath(path)


@evaluates("tex_ies")
def eval_ies(ev, e):
    ev.approx(e, "IES profile approximated by its strength alone")
    return 1.0


@maps("ShaderNodeTexGradient")
def tex_gradient(ctx, node, socket):
    return Expr("tex_gradient", ctx.label(node), {"vector": ctx.input(node, "Vector", default=(0, 0, 0))},
                {"output": getattr(socket, "identifier", "Color"),
                 "gradient_type": getattr(node, "gradient_type", "LINEAR")})


@evaluates("tex_gradient")
def eval_gradient(ev, e):
    ev.approx(e, "gradient texture approximated by its average")
    return 0.5 if e.props.get("output") == "Fac" else (0.5, 0.5, 0.5)


# ---- Blender's other procedural textures: the engine computes each as Cycles 3.4 does
# (engine/src/textures/voronoi.h, musgrave.h, pattern_textures.h). Without the engine
# (constant evaluation) each is its average, recorded as approximated.

def _inputs(ctx, node, names):
    return {key: ctx.input(node, name, default=d) for key, name, d in names}


@maps("ShaderNodeTexVoronoi")
def tex_voronoi(ctx, node, socket):
    args = _inputs(ctx, node, (("vector", "Vector", (0, 0, 0)), ("w", "W", 0.0), ("scale", "Scale", 5.0),
                               ("smoothness", "Smoothness", 1.0), ("exponent", "Exponent", 0.5),
                               ("randomness", "Randomness", 1.0)))
    detail = ctx.input_const(node, "Detail", default=0.0)  # Blender 4's fractal Voronoi
    if detail is None or float(detail) != 0.0:
        ctx.warn(node, "fractal Voronoi (Blender 4 Detail above 0) approximated by its first octave")
    return Expr("tex_voronoi", ctx.label(node), args, {
        "output": getattr(socket, "identifier", "Distance"),
        "dimensions": getattr(node, "voronoi_dimensions", "3D"),
        "feature": getattr(node, "feature", "F1"),
        "distance": getattr(node, "distance", "EUCLIDEAN")})


@maps("ShaderNodeTexMusgrave")
def tex_musgrave(ctx, node, socket):
    args = _inputs(ctx, node, (("vector", "Vector", (0, 0, 0)), ("w", "W", 0.0), ("scale", "Scale", 5.0),
                               ("detail", "Detail", 2.0), ("dimension", "Dimension", 2.0),
                               ("lacunarity", "Lacunarity", 2.0), ("offset", "Offset", 0.0), ("gain", "Gain", 1.0)))
    return Expr("tex_musgrave", ctx.label(node), args, {
        "output": "Fac", "dimensions": getattr(node, "musgrave_dimensions", "3D"),
        "musgrave_type": getattr(node, "musgrave_type", "FBM")})


@maps("ShaderNodeTexWave")
def tex_wave(ctx, node, socket):
    args = _inputs(ctx, node, (("vector", "Vector", (0, 0, 0)), ("scale", "Scale", 5.0),
                               ("distortion", "Distortion", 0.0), ("detail", "Detail", 2.0),
                               ("detail_scale", "Detail Scale", 1.0), ("detail_roughness", "Detail Roughness", 0.5),
                               ("phase", "Phase Offset", 0.0)))
    wave_type = getattr(node, "wave_type", "BANDS")
    direction = getattr(node, "bands_direction" if wave_type == "BANDS" else "rings_direction", "X")
    return Expr("tex_wave", ctx.label(node), args, {
        "output": getattr(socket, "identifier", "Color"), "wave_type": wave_type, "direction": direction,
        "profile": getattr(node, "wave_profile", "SIN")})


@maps("ShaderNodeTexMagic")
def tex_magic(ctx, node, socket):
    args = _inputs(ctx, node, (("vector", "Vector", (0, 0, 0)), ("scale", "Scale", 5.0),
                               ("distortion", "Distortion", 1.0)))
    return Expr("tex_magic", ctx.label(node), args, {
        "output": getattr(socket, "identifier", "Color"), "depth": int(getattr(node, "turbulence_depth", 2))})


@maps("ShaderNodeTexBrick")
def tex_brick(ctx, node, socket):
    args = _inputs(ctx, node, (("vector", "Vector", (0, 0, 0)), ("color1", "Color1", (0.8, 0.8, 0.8)),
                               ("color2", "Color2", (0.2, 0.2, 0.2)), ("mortar", "Mortar", (0.0, 0.0, 0.0)),
                               ("scale", "Scale", 5.0), ("mortar_size", "Mortar Size", 0.02),
                               ("mortar_smooth", "Mortar Smooth", 0.1), ("bias", "Bias", 0.0),
                               ("brick_width", "Brick Width", 0.5), ("row_height", "Row Height", 0.25)))
    return Expr("tex_brick", ctx.label(node), args, {
        "output": getattr(socket, "identifier", "Color"),
        "offset": float(getattr(node, "offset", 0.5)), "offset_frequency": int(getattr(node, "offset_frequency", 2)),
        "squash": float(getattr(node, "squash", 1.0)), "squash_frequency": int(getattr(node, "squash_frequency", 2))})


@maps("ShaderNodeTexWhiteNoise")
def tex_white_noise(ctx, node, socket):
    args = _inputs(ctx, node, (("vector", "Vector", (0, 0, 0)), ("w", "W", 0.0)))
    return Expr("tex_white_noise", ctx.label(node), args, {
        "output": getattr(socket, "identifier", "Value"), "dimensions": getattr(node, "noise_dimensions", "3D")})


# Each output's average over the plane, for constant evaluation (fac / value outputs
# by their typical level; colours grey).
_AVERAGES = {
    "tex_voronoi": {"Distance": 0.4, "W": 0.0, "Radius": 0.3, "Position": (0.0, 0.0, 0.0)},
    "tex_musgrave": {"Fac": 0.0},
}


@evaluates("tex_voronoi", "tex_musgrave", "tex_wave", "tex_magic", "tex_brick", "tex_white_noise")
def eval_procedural(ev, e):
    name = e.op[len("tex_"):].replace("_", " ")
    ev.approx(e, "%s texture approximated by its average" % name)
    out = e.props.get("output")
    if e.op == "tex_brick" and out == "Color":
        c1, c2 = ev.color(e.args["color1"]), ev.color(e.args["color2"])
        return tuple(0.5 * (a + b) for a, b in zip(c1, c2))
    v = _AVERAGES.get(e.op, {}).get(out, 0.5)
    if isinstance(v, tuple) or out in ("Color",):
        return v if isinstance(v, tuple) else (v, v, v)
    return float(v)
