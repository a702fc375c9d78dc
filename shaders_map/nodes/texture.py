"""Texture nodes: Image, Environment, Checker, Noise, Gradient.

Lowering to today's engine replaces each texture by its average colour (with a warning);
the IR keeps everything a textured engine material will need.
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


@maps("ShaderNodeTexGradient")
def tex_gradient(ctx, node, socket):
    return Expr("tex_gradient", ctx.label(node), {"vector": ctx.input(node, "Vector", default=(0, 0, 0))},
                {"output": getattr(socket, "identifier", "Color"),
                 "gradient_type": getattr(node, "gradient_type", "LINEAR")})


@evaluates("tex_gradient")
def eval_gradient(ev, e):
    ev.approx(e, "gradient texture approximated by its average")
    return 0.5 if e.props.get("output") == "Fac" else (0.5, 0.5, 0.5)
