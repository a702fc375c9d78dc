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
    dtype = getattr(node, "data_type", "FLOAT")
    if dtype != "FLOAT":
        ctx.warn(node, "vector map range approximated")
    return Expr("map_range", ctx.label(node), {
        "value": ctx.input(node, "Value", default=1.0),
        "from_min": ctx.input(node, "From Min", "From_Min", default=0.0),
        "from_max": ctx.input(node, "From Max", "From_Max", default=1.0),
        "to_min": ctx.input(node, "To Min", "To_Min", default=0.0),
        "to_max": ctx.input(node, "To Max", "To_Max", default=1.0),
    }, {"interpolation_type": getattr(node, "interpolation_type", "LINEAR"),
        "clamp": getattr(node, "clamp", True)})


@evaluates("map_range")
def eval_map_range(ev, e):
    v = ev.float(e.args["value"])
    a, b = ev.float(e.args["from_min"]), ev.float(e.args["from_max"])
    c, d = ev.float(e.args["to_min"]), ev.float(e.args["to_max"])
    f = (v - a) / (b - a) if b != a else 0.0
    it = e.props.get("interpolation_type", "LINEAR")
    if it == "STEPPED":
        ev.approx(e, "stepped interpolation approximated as linear")
    elif it == "SMOOTHSTEP":
        f = min(max(f, 0.0), 1.0)
        f = f * f * (3.0 - 2.0 * f)
    elif it == "SMOOTHERSTEP":
        f = min(max(f, 0.0), 1.0)
        f = f * f * f * (f * (f * 6.0 - 15.0) + 10.0)
    r = c + f * (d - c)
    if e.props.get("clamp", True) and it == "LINEAR":
        r = min(max(r, min(c, d)), max(c, d))
    return r


VMATH = {
    "ADD": lambda a, b, s: tuple(x + y for x, y in zip(a, b)),
    "SUBTRACT": lambda a, b, s: tuple(x - y for x, y in zip(a, b)),
    "MULTIPLY": lambda a, b, s: tuple(x * y for x, y in zip(a, b)),
    "DIVIDE": lambda a, b, s: tuple(_safe_div(x, y) for x, y in zip(a, b)),
    "SCALE": lambda a, b, s: tuple(x * s for x in a),
    "DOT_PRODUCT": lambda a, b, s: sum(x * y for x, y in zip(a, b)),
    "LENGTH": lambda a, b, s: math.sqrt(sum(x * x for x in a)),
    "ABSOLUTE": lambda a, b, s: tuple(abs(x) for x in a),
    "MINIMUM": lambda a, b, s: tuple(min(x, y) for x, y in zip(a, b)),
    "MAXIMUM": lambda a, b, s: tuple(max(x, y) for x, y in zip(a, b)),
    "NORMALIZE": lambda a, b, s: (lambda l: tuple(x / l for x in a) if l > 0 else (0.0, 0.0, 0.0))(
        math.sqrt(sum(x * x for x in a))),
}


@maps("ShaderNodeVectorMath")
def vector_math(ctx, node, socket):
    ins = list(getattr(node, "inputs", ()))
    vecs = [s for s in ins if getattr(s, "type", "") == "VECTOR"]
    scale = ctx.input(node, "Scale", default=1.0)
    args = {"a": ctx.eval_input(node, vecs[0]) if vecs else None,
            "b": ctx.eval_input(node, vecs[1]) if len(vecs) > 1 else None,
            "scale": scale}
    return Expr("vector_math", ctx.label(node), {k: v for k, v in args.items() if v is not None}, {
        "operation": getattr(node, "operation", "ADD"),
        "output": getattr(socket, "identifier", "Vector")})


@evaluates("vector_math")
def eval_vector_math(ev, e):
    op = e.props.get("operation", "ADD")
    a = ev.color(e.args["a"]) if "a" in e.args else (0.0, 0.0, 0.0)
    b = ev.color(e.args["b"]) if "b" in e.args else (0.0, 0.0, 0.0)
    s = ev.float(e.args["scale"]) if "scale" in e.args else 1.0
    fn = VMATH.get(op)
    if fn is None:
        ev.approx(e, "vector math %s not evaluated" % op)
        r = (0.0, 0.0, 0.0)
    else:
        r = fn(a, b, s)
    if e.props.get("output") == "Value":
        return r if isinstance(r, float) else 0.0
    return r if not isinstance(r, float) else (r, r, r)
