"""Converter nodes: Math, Clamp, Map Range, Vector Math."""

import math

from ..ir import Expr
from ..registry import maps, evaluates


def _safe_div(a, b):
    return a / b if b != 0.0 else 0.0


def _safe_pow(a, b):
    if a < 0.0 and b != int(b):
        return 0.0
    try:
        return math.pow(a, b)
    except (OverflowError, ValueError, ZeroDivisionError):
        return 0.0


def _safe_log(a, b):
    return math.log(a) / math.log(b) if a > 0.0 and b > 0.0 and b != 1.0 else 0.0


def _fmod(a, b):
    return math.fmod(a, b) if b != 0.0 else 0.0


def _wrap(v, hi, lo):
    r = hi - lo
    return v - r * math.floor((v - lo) / r) if r != 0.0 else lo


def _pingpong(a, b):
    return abs(_fmod(a - b, b * 2.0) - b) if b != 0.0 else 0.0


def _smoothmin(a, b, c):
    if c != 0.0:
        h = max(c - abs(a - b), 0.0) / c
        return min(a, b) - h * h * h * c * (1.0 / 6.0)
    return min(a, b)


MATH = {
    "ADD": lambda a, b, c: a + b,
    "SUBTRACT": lambda a, b, c: a - b,
    "MULTIPLY": lambda a, b, c: a * b,
    "DIVIDE": lambda a, b, c: _safe_div(a, b),
    "MULTIPLY_ADD": lambda a, b, c: a * b + c,
    "POWER": lambda a, b, c: _safe_pow(a, b),
    "LOGARITHM": lambda a, b, c: _safe_log(a, b),
    "SQRT": lambda a, b, c: math.sqrt(a) if a > 0.0 else 0.0,
    "INVERSE_SQRT": lambda a, b, c: 1.0 / math.sqrt(a) if a > 0.0 else 0.0,
    "ABSOLUTE": lambda a, b, c: abs(a),
    "EXPONENT": lambda a, b, c: math.exp(min(a, 700.0)),
    "MINIMUM": lambda a, b, c: min(a, b),
    "MAXIMUM": lambda a, b, c: max(a, b),
    "LESS_THAN": lambda a, b, c: 1.0 if a < b else 0.0,
    "GREATER_THAN": lambda a, b, c: 1.0 if a > b else 0.0,
    "SIGN": lambda a, b, c: (a > 0.0) - (a < 0.0) + 0.0,
    "COMPARE": lambda a, b, c: 1.0 if abs(a - b) <= max(c, 1e-5) else 0.0,
    "SMOOTH_MIN": lambda a, b, c: _smoothmin(a, b, c),
    "SMOOTH_MAX": lambda a, b, c: -_smoothmin(-a, -b, c),
    "ROUND": lambda a, b, c: math.floor(a + 0.5),
    "FLOOR": lambda a, b, c: math.floor(a),
    "CEIL": lambda a, b, c: math.ceil(a),
    "TRUNC": lambda a, b, c: float(math.trunc(a)),
    "FRACT": lambda a, b, c: a - math.floor(a),
    "MODULO": lambda a, b, c: _fmod(a, b),
    "WRAP": lambda a, b, c: _wrap(a, b, c),
    "SNAP": lambda a, b, c: math.floor(_safe_div(a, b)) * b,
    "PINGPONG": lambda a, b, c: _pingpong(a, b),
    "SINE": lambda a, b, c: math.sin(a),
    "COSINE": lambda a, b, c: math.cos(a),
    "TANGENT": lambda a, b, c: math.tan(a),
    "ARCSINE": lambda a, b, c: math.asin(a) if -1.0 <= a <= 1.0 else 0.0,
    "ARCCOSINE": lambda a, b, c: math.acos(a) if -1.0 <= a <= 1.0 else 0.0,
    "ARCTANGENT": lambda a, b, c: math.atan(a),
    "ARCTAN2": lambda a, b, c: math.atan2(a, b),
    "SINH": lambda a, b, c: math.sinh(max(min(a, 700.0), -700.0)),
    "COSH": lambda a, b, c: math.cosh(max(min(a, 700.0), -700.0)),
    "TANH": lambda a, b, c: math.tanh(a),
    "RADIANS": lambda a, b, c: math.radians(a),
    "DEGREES": lambda a, b, c: math.degrees(a),
}


@maps("ShaderNodeMath")
def math_node(ctx, node, socket):
    ins = [s for s in getattr(node, "inputs", ())]
    args = {}
    for key, s in zip(("a", "b", "c"), ins):
        args[key] = ctx.eval_input(node, s)
    return Expr("math", ctx.label(node), args, {
        "operation": getattr(node, "operation", "ADD"),
        "use_clamp": getattr(node, "use_clamp", False)})


@evaluates("math")
def eval_math(ev, e):
    op = e.props.get("operation", "ADD")
    a, b, c = (ev.float(e.args[k]) if k in e.args else 0.0 for k in ("a", "b", "c"))
    fn = MATH.get(op)
    if fn is None:
        ev.approx(e, "math operation %s not evaluated, using 0" % op)
        return 0.0
    try:
        v = float(fn(a, b, c))
    except (ValueError, OverflowError):
        v = 0.0
    if not math.isfinite(v):
        v = 0.0
    if e.props.get("use_clamp"):
        v = min(max(v, 0.0), 1.0)
    return v


@maps("ShaderNodeClamp")
def clamp(ctx, node, socket):
    return Expr("clamp", ctx.label(node), {
        "value": ctx.input(node, "Value", default=1.0),
        "min": ctx.input(node, "Min", default=0.0),
        "max": ctx.input(node, "Max", default=1.0)}, {"clamp_type": getattr(node, "clamp_type", "MINMAX")})


@evaluates("clamp")
def eval_clamp(ev, e):
    v, lo, hi = ev.float(e.args["value"]), ev.float(e.args["min"]), ev.float(e.args["max"])
    if e.props.get("clamp_type") == "RANGE" and lo > hi:
        lo, hi = hi, lo
    return min(max(v, lo), hi)


@maps("ShaderNodeMapRange")
def map_range(ctx, node, socket):
    vector = getattr(node, "data_type", "FLOAT") == "FLOAT_VECTOR"
    if vector:  # the vector sockets (Blender names them as the float ones; identifiers differ)
        names = (("value", "Vector", (0.0, 0.0, 0.0)), ("from_min", "From_Min_FLOAT3", (0.0, 0.0, 0.0)),
                 ("from_max", "From_Max_FLOAT3", (1.0, 1.0, 1.0)), ("to_min", "To_Min_FLOAT3", (0.0, 0.0, 0.0)),
                 ("to_max", "To_Max_FLOAT3", (1.0, 1.0, 1.0)), ("steps", "Steps_FLOAT3", (4.0, 4.0, 4.0)))
        args = {k: ctx.input(node, n, default=d) for k, n, d in names}
    else:
        args = {"value": ctx.input(node, "Value", default=1.0),
                "from_min": ctx.input(node, "From Min", "From_Min", default=0.0),
                "from_max": ctx.input(node, "From Max", "From_Max", default=1.0),
                "to_min": ctx.input(node, "To Min", "To_Min", default=0.0),
                "to_max": ctx.input(node, "To Max", "To_Max", default=1.0),
                "steps": ctx.input(node, "Steps", default=4.0)}
    return Expr("map_range", ctx.label(node), args, {
        "interpolation_type": getattr(node, "interpolation_type", "LINEAR"),
        "clamp": bool(getattr(node, "clamp", True)), "vector": vector})


def _smoothstep(e0, e1, x):
    if x < e0:
        return 0.0
    if x >= e1:
        return 1.0
    t = (x - e0) / (e1 - e0)
    return (3.0 - 2.0 * t) * t * t


def _smootherstep(e0, e1, x):
    x = min(max(_safe_div(x - e0, e1 - e0), 0.0), 1.0)
    return x * x * x * (x * (x * 6.0 - 15.0) + 10.0)


def _clamp_between(v, a, b):
    return min(max(v, b), a) if a > b else min(max(v, a), b)


def _map_range_float(v, a, b, c, d, steps, kind, clamp):
    """Cycles' svm_node_map_range (and the Clamp it adds for linear and stepped)."""
    if a == b:
        return 0.0
    f = (v - a) / (b - a)
    if kind == "STEPPED":
        f = math.floor(f * (steps + 1.0)) / steps if steps > 0.0 else 0.0
    elif kind == "SMOOTHSTEP":
        f = 1.0 - _smoothstep(b, a, v) if a > b else _smoothstep(a, b, v)
    elif kind == "SMOOTHERSTEP":
        f = 1.0 - _smootherstep(b, a, v) if a > b else _smootherstep(a, b, v)
    r = c + f * (d - c)
    return _clamp_between(r, c, d) if clamp and kind in ("LINEAR", "STEPPED") else r


def _map_range_component(v, a, b, c, d, steps, kind, clamp):
    """One component of Cycles' svm_node_vector_map_range."""
    f = _safe_div(v - a, b - a)
    if kind == "STEPPED":
        f = math.floor(f * (steps + 1.0)) / steps if steps > 0.0 else 0.0
    elif kind in ("SMOOTHSTEP", "SMOOTHERSTEP"):
        t = min(max(f, 0.0), 1.0)
        f = (3.0 - 2.0 * t) * t * t if kind == "SMOOTHSTEP" else t * t * t * (t * (t * 6.0 - 15.0) + 10.0)
    r = c + f * (d - c)
    return _clamp_between(r, c, d) if clamp and kind in ("LINEAR", "STEPPED") else r


@evaluates("map_range")
def eval_map_range(ev, e):
    kind, clamp = e.props.get("interpolation_type", "LINEAR"), e.props.get("clamp", True)
    keys = ("value", "from_min", "from_max", "to_min", "to_max", "steps")
    if e.props.get("vector"):
        vs = [ev.color(e.args[k]) for k in keys]
        return tuple(_map_range_component(*(v[i] for v in vs), kind, clamp) for i in range(3))
    return _map_range_float(*(ev.float(e.args[k]) for k in keys), kind, clamp)


def _dot(a, b):
    return sum(x * y for x, y in zip(a, b))


def _normalize(a, safe=True):
    n = math.sqrt(_dot(a, a))
    return tuple(x / n for x in a) if n != 0.0 else (tuple(a) if safe else (float("nan"),) * 3)


def _refract(a, b, eta):
    n = _normalize(b)
    d = _dot(n, a)
    k = 1.0 - eta * eta * (1.0 - d * d)
    return (0.0, 0.0, 0.0) if k < 0.0 else tuple(eta * x - (eta * d + math.sqrt(k)) * y for x, y in zip(a, n))


def _per(fn):
    return lambda a, b, c, s: tuple(fn(x) for x in a)


# Cycles' svm_vector_math, operation by operation (a, b, c the three vectors, s the scale).
VMATH = {
    "ADD": lambda a, b, c, s: tuple(x + y for x, y in zip(a, b)),
    "SUBTRACT": lambda a, b, c, s: tuple(x - y for x, y in zip(a, b)),
    "MULTIPLY": lambda a, b, c, s: tuple(x * y for x, y in zip(a, b)),
    "DIVIDE": lambda a, b, c, s: tuple(_safe_div(x, y) for x, y in zip(a, b)),
    "MULTIPLY_ADD": lambda a, b, c, s: tuple(x * y + z for x, y, z in zip(a, b, c)),
    "CROSS_PRODUCT": lambda a, b, c, s: (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]),
    "PROJECT": lambda a, b, c, s: (lambda l2: tuple(_dot(a, b) / l2 * y for y in b) if l2 != 0.0 else (0.0, 0.0, 0.0))(
        _dot(b, b)),
    "REFLECT": lambda a, b, c, s: (lambda n: tuple(x - 2.0 * y * _dot(a, n) for x, y in zip(a, n)))(_normalize(b, False)),
    "REFRACT": lambda a, b, c, s: _refract(a, b, s),
    "FACEFORWARD": lambda a, b, c, s: tuple(a) if _dot(c, b) < 0.0 else tuple(-x for x in a),
    "DOT_PRODUCT": lambda a, b, c, s: _dot(a, b),
    "DISTANCE": lambda a, b, c, s: math.sqrt(sum((x - y) ** 2 for x, y in zip(a, b))),
    "LENGTH": lambda a, b, c, s: math.sqrt(_dot(a, a)),
    "SCALE": lambda a, b, c, s: tuple(x * s for x in a),
    "NORMALIZE": lambda a, b, c, s: _normalize(a),
    "SNAP": lambda a, b, c, s: tuple(math.floor(_safe_div(x, y)) * y for x, y in zip(a, b)),
    "FLOOR": _per(math.floor),
    "CEIL": _per(math.ceil),
    "MODULO": lambda a, b, c, s: tuple(math.fmod(x, y) if y != 0.0 else 0.0 for x, y in zip(a, b)),
    "WRAP": lambda a, b, c, s: tuple(_wrap(x, y, z) for x, y, z in zip(a, b, c)),
    "FRACTION": _per(lambda x: x - math.floor(x)),
    "ABSOLUTE": _per(abs),
    "MINIMUM": lambda a, b, c, s: tuple(min(x, y) for x, y in zip(a, b)),
    "MAXIMUM": lambda a, b, c, s: tuple(max(x, y) for x, y in zip(a, b)),
    "SINE": _per(math.sin),
    "COSINE": _per(math.cos),
    "TANGENT": _per(math.tan),
}


@maps("ShaderNodeVectorMath")
def vector_math(ctx, node, socket):
    ins = list(getattr(node, "inputs", ()))
    vecs = [s for s in ins if getattr(s, "type", "") == "VECTOR"]
    args = {"a": ctx.eval_input(node, vecs[0]) if vecs else None,
            "b": ctx.eval_input(node, vecs[1]) if len(vecs) > 1 else None,
            "c": ctx.eval_input(node, vecs[2]) if len(vecs) > 2 else None,
            "scale": ctx.input(node, "Scale", default=1.0)}
    return Expr("vector_math", ctx.label(node), {k: v for k, v in args.items() if v is not None}, {
        "operation": getattr(node, "operation", "ADD"),
        "output": getattr(socket, "identifier", "Vector")})


@evaluates("vector_math")
def eval_vector_math(ev, e):
    op = e.props.get("operation", "ADD")
    a, b, c = (ev.color(e.args[k]) if k in e.args else (0.0, 0.0, 0.0) for k in ("a", "b", "c"))
    s = ev.float(e.args["scale"]) if "scale" in e.args else 1.0
    fn = VMATH.get(op)
    if fn is None:
        ev.approx(e, "vector math %s not evaluated" % op)
        r = (0.0, 0.0, 0.0)
    else:
        try:
            r = fn(a, b, c, s)
        except (ValueError, OverflowError):
            r = (0.0, 0.0, 0.0)
    if isinstance(r, tuple) and not all(math.isfinite(x) for x in r):
        r = (0.0, 0.0, 0.0)
    if e.props.get("output") == "Value":
        return r if isinstance(r, float) else 0.0
    return r if not isinstance(r, float) else (r, r, r)


# Light Falloff: Strength times the length of the ray the emitted light travels (Cycles' ray
# length) to the power 0 (Quadratic: the physical falloff lamps already have), 1 (Linear) or 2
# (Constant), times d^2 / (Smooth + d^2) when Smooth > 0. The engine knows that length where light
# is emitted (lamps, emission shaders); the lowering reads it there (shaders_map/lowering.py).
@maps("ShaderNodeLightFalloff")
def light_falloff(ctx, node, socket):
    output = str(getattr(socket, "identifier", "Quadratic")).upper()
    return Expr("light_falloff", ctx.label(node), {
        "strength": ctx.input(node, "Strength", default=100.0),
        "smooth": ctx.input(node, "Smooth", default=0.0)}, {"output": output})


def falloff_at(output, strength, smooth, d):
    """Cycles 3.4's svm_node_light_falloff at ray length d."""
    if output == "LINEAR":
        strength *= d
    elif output == "CONSTANT":
        strength *= d * d
    if smooth > 0.0:
        strength *= d * d / (smooth + d * d)
    return strength


@evaluates("light_falloff")
def eval_light_falloff(ev, e):
    """At the evaluator's ray length (0 on the world and in volumes, as Cycles 3.4 sets it);
    unknown (None): Strength, an approximation unless the falloff is Quadratic without Smooth."""
    output = e.props.get("output", "QUADRATIC")
    strength, smooth = ev.float(e.args["strength"]), ev.float(e.args["smooth"])
    d = getattr(ev, "ray_length", None)
    if d is not None:
        return falloff_at(output, strength, smooth, d)
    if "name" in e.props:  # Light Path's Ray Length
        ev.approx(e, "Ray Length outside an emitter's colour or strength: a constant 1")
    elif output != "QUADRATIC" or smooth > 0.0:
        ev.approx(e, "%s falloff where the ray's length is not known: its Strength used" % output.title())
    return strength
