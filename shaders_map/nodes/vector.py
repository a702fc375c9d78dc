"""Vector nodes: Texture Coordinate, UV Map, Mapping, Normal Map, Bump, Bevel, (Vector) Displacement."""

import math

from ..ir import Expr
from ..registry import maps, evaluates


@maps("ShaderNodeTexCoord")
def texcoord(ctx, node, socket):
    obj = getattr(node, "object", None)
    return Expr("texcoord", ctx.label(node), {}, {
        "output": getattr(socket, "identifier", "Generated"),
        "object": getattr(obj, "name", None),
        "from_instancer": getattr(node, "from_instancer", False)})


@maps("ShaderNodeUVMap")
def uvmap(ctx, node, socket):
    return Expr("uvmap", ctx.label(node), {}, {
        "uv_map": getattr(node, "uv_map", ""),
        "from_instancer": getattr(node, "from_instancer", False)})


@evaluates("texcoord", "uvmap")
def eval_coords(ev, e):
    ev.approx(e, "texture coordinates vary over the surface")
    return (0.0, 0.0, 0.0)


@maps("ShaderNodeMapping")
def mapping(ctx, node, socket):
    vtype = getattr(node, "vector_type", "POINT")
    return Expr("mapping", ctx.label(node), {
        "vector": ctx.input(node, "Vector", default=(0, 0, 0)),
        "location": ctx.input(node, "Location", default=(0, 0, 0)),
        "rotation": ctx.input(node, "Rotation", default=(0, 0, 0)),
        "scale": ctx.input(node, "Scale", default=(1, 1, 1)),
    }, {"vector_type": vtype})


def _euler_xyz(r):
    cx, cy, cz = math.cos(r[0]), math.cos(r[1]), math.cos(r[2])
    sx, sy, sz = math.sin(r[0]), math.sin(r[1]), math.sin(r[2])
    # R = Rz * Ry * Rx (Blender's XYZ Euler)
    return (
        (cy * cz, sx * sy * cz - cx * sz, cx * sy * cz + sx * sz),
        (cy * sz, sx * sy * sz + cx * cz, cx * sy * sz - sx * cz),
        (-sy, sx * cy, cx * cy),
    )


def _mul(m, v):
    return tuple(m[i][0] * v[0] + m[i][1] * v[1] + m[i][2] * v[2] for i in range(3))


def _mul_t(m, v):
    return tuple(m[0][i] * v[0] + m[1][i] * v[1] + m[2][i] * v[2] for i in range(3))


@evaluates("mapping")
def eval_mapping(ev, e):
    v = ev.color(e.args["vector"])
    loc = ev.color(e.args["location"])
    rot = _euler_xyz(ev.color(e.args["rotation"]))
    s = ev.color(e.args["scale"])
    t = e.props.get("vector_type", "POINT")
    if t == "POINT":
        return tuple(a + b for a, b in zip(_mul(rot, tuple(x * y for x, y in zip(v, s))), loc))
    if t == "TEXTURE":
        d = _mul_t(rot, tuple(a - b for a, b in zip(v, loc)))
        return tuple(x / y if y != 0.0 else 0.0 for x, y in zip(d, s))
    if t == "VECTOR":
        return _mul(rot, tuple(x * y for x, y in zip(v, s)))
    # NORMAL
    n = _mul(rot, tuple(x / y if y != 0.0 else 0.0 for x, y in zip(v, s)))
    length = math.sqrt(sum(x * x for x in n))
    return tuple(x / length for x in n) if length > 0 else n


@maps("ShaderNodeNormalMap")
def normal_map(ctx, node, socket):
    return Expr("normal_map", ctx.label(node), {
        "strength": ctx.input(node, "Strength", default=1.0),
        "color": ctx.input(node, "Color", default=(0.5, 0.5, 1.0)),
    }, {"space": getattr(node, "space", "TANGENT"), "uv_map": getattr(node, "uv_map", "")})


@maps("ShaderNodeBump")
def bump(ctx, node, socket):
    return Expr("bump", ctx.label(node), {
        "strength": ctx.input(node, "Strength", default=1.0),
        "distance": ctx.input(node, "Distance", default=1.0),
        "height": ctx.input(node, "Height", default=1.0),
        "normal": ctx.input(node, "Normal", default=(0, 0, 0)),
    }, {"invert": getattr(node, "invert", False)})


# Bevel: the engine averages the object's normals within Radius (textures/bevel.h); Normal,
# when linked, is offset by the bevel's turn. Dropped on blurry rays (ray_kinds.py).
@maps("ShaderNodeBevel")
def bevel(ctx, node, socket):
    return Expr("bevel", ctx.label(node), {
        "radius": ctx.input(node, "Radius", default=0.05),
        "normal": ctx.input(node, "Normal", default=(0, 0, 0)),
    }, {"samples": int(getattr(node, "samples", 4))})


# Displacement: the offset (Height - Midlevel) x Scale along the normal (Normal, else the shading
# normal), in world space; taken in object space (the object's scale applies) when Space is Object.
# Into the Material Output's Displacement it bumps the material's normal (lowering.py).
@maps("ShaderNodeDisplacement")
def displacement(ctx, node, socket):
    args = {"height": ctx.input(node, "Height", default=0.0),
            "midlevel": ctx.input(node, "Midlevel", default=0.5),
            "scale": ctx.input(node, "Scale", default=1.0)}
    if ctx.is_linked(node, "Normal"):
        args["normal"] = ctx.input(node, "Normal", default=(0, 0, 0))
    return Expr("displacement", ctx.label(node), args, {"space": getattr(node, "space", "OBJECT")})


# Vector Displacement: (Vector - Midlevel) x Scale, in tangent space (x along the tangent, y
# along the normal, z along the bitangent: Blender's maps), object or world space.
@maps("ShaderNodeVectorDisplacement")
def vector_displacement(ctx, node, socket):
    return Expr("vector_displacement", ctx.label(node), {
        "vector": ctx.input(node, "Vector", default=(0.0, 0.0, 0.0)),
        "midlevel": ctx.input(node, "Midlevel", default=0.0),
        "scale": ctx.input(node, "Scale", default=1.0)}, {"space": getattr(node, "space", "TANGENT")})


@evaluates("vector_displacement")
def eval_vector_displacement(ev, e):
    ev.approx(e, "vector displacement approximated by its vector in world space")
    v, m, s = ev.color(e.args["vector"]), ev.float(e.args["midlevel"]), ev.float(e.args["scale"])
    return tuple((x - m) * s for x in v)


@evaluates("displacement")
def eval_displacement(ev, e):
    ev.approx(e, "displacement along the normal approximated by one along +Z")
    k = (ev.float(e.args["height"]) - ev.float(e.args["midlevel"])) * ev.float(e.args["scale"])
    return (0.0, 0.0, k)


@evaluates("normal_map", "bump", "bevel")
def eval_normal(ev, e):
    ev.approx(e, "normal perturbation ignored")
    return (0.0, 0.0, 0.0)
