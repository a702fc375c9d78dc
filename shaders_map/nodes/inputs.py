"""Input nodes: RGB, Value, Vertex Color (Color Attribute), Attribute."""

from ..ir import Const, Expr
from ..registry import maps, evaluates


@maps("ShaderNodeRGB")
def rgb(ctx, node, socket):
    outs = list(getattr(node, "outputs", ()))
    return ctx.constant(node, outs[0]) if outs else Const((0.5, 0.5, 0.5))


@maps("ShaderNodeValue")
def value(ctx, node, socket):
    outs = list(getattr(node, "outputs", ()))
    return ctx.constant(node, outs[0]) if outs else Const(0.0)


@maps("ShaderNodeVertexColor")
def vertex_color(ctx, node, socket):
    return Expr("vertex_color", ctx.label(node), {}, {
        "layer_name": getattr(node, "layer_name", ""),
        "output": getattr(socket, "identifier", "Color")})


@maps("ShaderNodeAttribute")
def attribute(ctx, node, socket):
    return Expr("attribute", ctx.label(node), {}, {
        "attribute_name": getattr(node, "attribute_name", ""),
        "attribute_type": getattr(node, "attribute_type", "GEOMETRY"),
        "output": getattr(socket, "identifier", "Color")})


@evaluates("vertex_color", "attribute")
def eval_attribute(ev, e):
    ev.approx(e, "per-vertex colour/attribute approximated by white")
    out = e.props.get("output", "Color")
    if out in ("Fac", "Alpha"):
        return 1.0
    return (1.0, 1.0, 1.0)


# Object Info: the engine reads the instance's Blender random number, colour, alpha and
# pass index and the material's pass index (the add-on exports them with each instance).
OBJECT_INFO_OUTPUTS = {"Location": "location", "Color": "color", "Alpha": "alpha", "Object Index": "object_index",
                       "Material Index": "material_index", "Random": "random"}


@maps("ShaderNodeObjectInfo")
def object_info(ctx, node, socket):
    return Expr("object_info", ctx.label(node), {},
                {"output": OBJECT_INFO_OUTPUTS.get(getattr(socket, "identifier", "Random"), "random")})


@evaluates("object_info")
def eval_object_info(ev, e):
    ev.approx(e, "object info approximated by a typical object's (random 0.5, white)")
    out = e.props.get("output")
    if out in ("color",):
        return (1.0, 1.0, 1.0)
    if out == "location":
        return (0.0, 0.0, 0.0)
    return {"alpha": 1.0, "random": 0.5}.get(out, 0.0)


@maps("ShaderNodeNewGeometry")
def geometry(ctx, node, socket):
    return Expr("geometry", ctx.label(node), {}, {"output": getattr(socket, "identifier", "Position")})


@evaluates("geometry")
def eval_geometry(ev, e):
    out = e.props.get("output")
    if out in ("Position", "Normal", "True Normal"):
        ev.approx(e, "geometry %s approximated by a constant without the engine" % out)
    else:  # Incoming, Backfacing (the viewer's side), Tangent, Parametric, Pointiness, Random per Island
        ev.approx(e, "geometry %s not supported, a constant" % out)
    return 0.0 if out in ("Backfacing", "Pointiness", "Random Per Island") else (0.0, 0.0, 1.0)
