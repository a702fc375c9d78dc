"""Input nodes: RGB, Value, Vertex Color (Color Attribute), Attribute, Object Info, Geometry,
Fresnel, Layer Weight, Light Path."""

import math

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


# Camera Data: the shading point in the camera's space (Cycles' svm_node_camera: x right, y up,
# z toward where the camera looks), a function of the point alone, whatever ray reached it.
CAMERA_DATA_OUTPUTS = {"View Vector": "view_vector", "View Z Depth": "view_z_depth", "View Distance": "view_distance"}


@maps("ShaderNodeCameraData")
def camera_data(ctx, node, socket):
    return Expr("camera_data", ctx.label(node), {},
                {"output": CAMERA_DATA_OUTPUTS.get(getattr(socket, "identifier", "View Vector"), "view_vector")})


@evaluates("camera_data")
def eval_camera_data(ev, e):
    ev.approx(e, "camera data approximated by a point 1 unit in front of the camera")
    return (0.0, 0.0, 1.0) if e.props.get("output") == "view_vector" else 1.0


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


# Geometry > Pointiness and Random Per Island are values Cycles derives from the mesh; the
# exporter computes them the same way (export/mesh.py) and sends them as per-vertex attributes
# under these names, which the material reads as an Attribute node's Fac.
MESH_DERIVED_ATTRIBUTES = {"Pointiness": "__rdv_pointiness", "Random Per Island": "__rdv_random_per_island"}


@maps("ShaderNodeNewGeometry")
def geometry(ctx, node, socket):
    output = getattr(socket, "identifier", "Position")
    if output in MESH_DERIVED_ATTRIBUTES:
        return Expr("attribute", ctx.label(node), {}, {"attribute_name": MESH_DERIVED_ATTRIBUTES[output],
                                                       "attribute_type": "GEOMETRY", "output": "Fac"})
    return Expr("geometry", ctx.label(node), {}, {"output": output})


@evaluates("geometry")
def eval_geometry(ev, e):
    out = e.props.get("output")
    if out in ("Position", "Normal", "True Normal", "Parametric", "Tangent"):
        ev.approx(e, "geometry %s approximated by a constant without the engine" % out)
    elif out == "Backfacing":  # the viewer's side: exact as a Mix Shader's Fac (lowering's view factors)
        ev.approx(e, "geometry Backfacing depends on the viewing direction: exact only as a Mix Shader's Fac; "
                     "here 0 (the front)")
    else:  # Incoming
        ev.approx(e, "geometry %s not supported, a constant" % out)
    return 0.0 if out == "Backfacing" else (0.0, 0.0, 1.0)


# Fresnel and Layer Weight depend on the viewing direction. As a Mix Shader's factor the engine
# evaluates them per pair of directions (lowering: "view factors"); anywhere else they are their
# cosine-weighted mean over the directions of a hemisphere, with a warning.
@maps("ShaderNodeFresnel")
def fresnel(ctx, node, socket):
    return Expr("fresnel", ctx.label(node), {"ior": ctx.input(node, "IOR", default=1.45)},
                {"normal_linked": ctx.is_linked(node, "Normal")})


@maps("ShaderNodeLayerWeight")
def layer_weight(ctx, node, socket):
    output = "facing" if getattr(socket, "identifier", "Fresnel") == "Facing" else "fresnel"
    return Expr("layer_weight", ctx.label(node), {"blend": ctx.input(node, "Blend", default=0.5)},
                {"output": output, "normal_linked": ctx.is_linked(node, "Normal")})


def _fresnel_dielectric_cos(c, eta):
    """Cycles' fresnel_dielectric_cos: reflectance at |cos| c of relative IOR eta."""
    g = eta * eta - 1 + c * c
    if g <= 0:
        return 1.0
    g = math.sqrt(g)
    a, b = (g - c) / (g + c), (c * (g + c) - 1) / (c * (g - c) + 1)
    return 0.5 * a * a * (1 + b * b)


def view_factor_value(op, param, output, cos):
    """The factor seen at |cos| from the front (Cycles' svm_node_fresnel / layer_weight)."""
    if op == "fresnel":
        return _fresnel_dielectric_cos(cos, min(max(param, 1e-5), 1e5))
    if output == "fresnel":
        return _fresnel_dielectric_cos(cos, 1.0 / min(max(1.0 - param, 1e-5), 1e5))
    f = cos
    if param != 0.5:
        b = min(max(param, 0.0), 1.0 - 1e-5)
        f = f ** (2.0 * b if b < 0.5 else 0.5 / (1.0 - b))
    return 1.0 - f


def view_factor_mean(op, param, output="fresnel"):
    """Cosine-weighted mean over the hemisphere (256 midpoints in cos^2, as the engine's)."""
    n = 256
    return sum(view_factor_value(op, param, output, math.sqrt((i + 0.5) / n)) for i in range(n)) / n


@evaluates("fresnel", "layer_weight")
def eval_view_factor(ev, e):
    param = ev.float(e.args.get("ior" if e.op == "fresnel" else "blend", Const(1.45 if e.op == "fresnel" else 0.5)))
    mean = view_factor_mean(e.op, param, e.props.get("output", "fresnel"))
    ev.approx(e, "depends on the viewing direction: exact only as a Mix Shader's Fac; here its mean "
                 "over directions, %.3f" % mean)
    return mean


# Light Path: its ray-type outputs are constants per kind of ray; a material or world that reads
# them is lowered once per kind (ray_kinds.py), which replaces them before evaluation. What is
# left here is what that cannot make exact: the depths, and a ray type read where no split
# applies (a volume shader). Ray Length is Light Falloff's d (Linear of strength 1): exact where
# light is emitted, as the falloff is (converter.py).
@maps("ShaderNodeLightPath")
def light_path(ctx, node, socket):
    output = getattr(socket, "identifier", "Is Camera Ray")
    if output == "Ray Length":
        return Expr("light_falloff", ctx.label(node), {"strength": Const(1.0), "smooth": Const(0.0)},
                    {"output": "LINEAR", "name": "Ray Length"})
    return Expr("light_path", ctx.label(node), {}, {"output": output})


@evaluates("light_path")
def eval_light_path(ev, e):
    out = e.props.get("output", "")
    if out.endswith("Depth"):
        ev.approx(e, "%s is not supported, 0 (as on a camera ray)" % out)
        return 0.0
    ev.approx(e, "%s here is 0 (the ray types are told apart only in a material's or world's surface)" % out)
    return 0.0


# Wireframe: 1 within half of Size of the triangle's edges (world units, or pixels with Pixel
# Size), computed by the engine from the hit's triangle (Blender's triangulation, as Cycles').
@maps("ShaderNodeWireframe")
def wireframe(ctx, node, socket):
    return Expr("wireframe", ctx.label(node), {"size": ctx.input(node, "Size", default=0.01)},
                {"pixel_size": bool(getattr(node, "use_pixel_size", False))})


@evaluates("wireframe")
def eval_wireframe(ev, e):
    ev.approx(e, "wireframe approximated by 0 (its faces) without the engine")
    return 0.0


# Ambient Occlusion: the engine traces its rays from the hit (textures/ambient_occlusion.h):
# Samples, Inside, Only Local as Cycles; the directions a fixed set per point, not drawn anew.
@maps("ShaderNodeAmbientOcclusion")
def ambient_occlusion(ctx, node, socket):
    return Expr("ao", ctx.label(node), {"color": ctx.input(node, "Color", default=(1.0, 1.0, 1.0)),
                                        "distance": ctx.input(node, "Distance", default=1.0)},
                {"samples": int(getattr(node, "samples", 16)), "inside": bool(getattr(node, "inside", False)),
                 "only_local": bool(getattr(node, "only_local", False)),
                 "output": "ao" if getattr(socket, "identifier", "Color") == "AO" else "color",
                 "normal_linked": ctx.is_linked(node, "Normal")})


@evaluates("ao")
def eval_ambient_occlusion(ev, e):
    ev.approx(e, "ambient occlusion approximated by 1 (nothing near) without the engine")
    return 1.0 if e.props.get("output") == "ao" else ev.color(e.args.get("color"))
