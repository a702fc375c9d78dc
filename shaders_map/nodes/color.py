"""Colour nodes: Mix RGB (legacy and 3.4+ Mix), Invert, Color Ramp, Gamma,
Bright/Contrast, Hue/Saturation, Separate/Combine colour, RGB to BW."""

import math

from ..ir import Expr, Const
from ..registry import maps, evaluates
from ..graph import to_float


def _clamp01(x):
    return 0.0 if x < 0.0 else 1.0 if x > 1.0 else x


@maps("ShaderNodeMixRGB")
def mix_rgb(ctx, node, socket):
    return Expr("mix_color", ctx.label(node), {
        "fac": ctx.input(node, "Fac", default=0.5),
        "a": ctx.input(node, "Color1", default=(0.5, 0.5, 0.5)),
        "b": ctx.input(node, "Color2", default=(0.5, 0.5, 0.5)),
    }, {"blend_type": getattr(node, "blend_type", "MIX"),
        "clamp_result": getattr(node, "use_clamp", False), "clamp_factor": True})


@maps("ShaderNodeMix")
def mix(ctx, node, socket):
    dtype = getattr(node, "data_type", "FLOAT")
    suffix = {"FLOAT": "Float", "VECTOR": "Vector", "RGBA": "Color"}.get(dtype, "Float")
    non_uniform = dtype == "VECTOR" and getattr(node, "factor_mode", "UNIFORM") == "NON_UNIFORM"
    fac = ctx.input(node, "Factor_Vector" if non_uniform else "Factor_Float", "Factor", default=0.5)
    a = ctx.input(node, "A_" + suffix, default=0.0)
    b = ctx.input(node, "B_" + suffix, default=0.0)
    props = {"clamp_factor": getattr(node, "clamp_factor", True),
             "clamp_result": getattr(node, "clamp_result", False)}
    if dtype == "RGBA":
        props["blend_type"] = getattr(node, "blend_type", "MIX")
        return Expr("mix_color", ctx.label(node), {"fac": fac, "a": a, "b": b}, props)
    props["data_type"] = dtype
    return Expr("mix_value", ctx.label(node), {"fac": fac, "a": a, "b": b}, props)


@evaluates("mix_value")
def eval_mix_value(ev, e):
    fac = ev.value(e.args["fac"])
    a, b = ev.value(e.args["a"]), ev.value(e.args["b"])
    if e.props.get("data_type") == "FLOAT":
        f = ev.float(e.args["fac"])
        if e.props.get("clamp_factor", True):
            f = _clamp01(f)
        return float((1 - f) * _f(a) + f * _f(b))
    av, bv = _v(a), _v(b)
    fv = _v(fac)
    if e.props.get("clamp_factor", True):
        fv = tuple(_clamp01(x) for x in fv)
    return tuple((1 - f) * x + f * y for f, x, y in zip(fv, av, bv))


def _f(v):
    return v if isinstance(v, float) else to_float(v)


def _v(v):
    return (v, v, v) if isinstance(v, float) else tuple(v)


def _blend(kind, t, a, b):
    """Blender's ramp_blend (per channel where it can be)."""
    tm = 1.0 - t
    if kind == "MIX":
        return tuple(tm * x + t * y for x, y in zip(a, b))
    if kind == "ADD":
        return tuple(x + t * y for x, y in zip(a, b))
    if kind == "MULTIPLY":
        return tuple(x * (tm + t * y) for x, y in zip(a, b))
    if kind == "SUBTRACT":
        return tuple(x - t * y for x, y in zip(a, b))
    if kind == "SCREEN":
        return tuple(1.0 - (tm + t * (1.0 - y)) * (1.0 - x) for x, y in zip(a, b))
    if kind == "DIVIDE":
        return tuple(tm * x + t * x / y if y != 0.0 else x for x, y in zip(a, b))
    if kind == "DIFFERENCE":
        return tuple(tm * x + t * abs(x - y) for x, y in zip(a, b))
    if kind == "DARKEN":
        return tuple(tm * x + t * min(x, y) for x, y in zip(a, b))
    if kind == "LIGHTEN":
        return tuple(tm * x + t * max(x, y) for x, y in zip(a, b))
    if kind == "OVERLAY":
        return tuple(x * (tm + 2.0 * t * y) if x < 0.5 else 1.0 - (tm + 2.0 * t * (1.0 - y)) * (1.0 - x)
                     for x, y in zip(a, b))
    if kind == "DODGE":
        out = []
        for x, y in zip(a, b):
            if x != 0.0:
                tmp = 1.0 - t * y
                out.append(1.0 if tmp <= 0.0 else min(x / tmp, 1.0))
            else:
                out.append(x)
        return tuple(out)
    if kind == "BURN":
        out = []
        for x, y in zip(a, b):
            tmp = tm + t * y
            out.append(0.0 if tmp <= 0.0 else _clamp01(1.0 - (1.0 - x) / tmp))
        return tuple(out)
    if kind == "SOFT_LIGHT":
        out = []
        for x, y in zip(a, b):
            scr = 1.0 - (1.0 - y) * (1.0 - x)
            out.append(tm * x + t * ((1.0 - x) * y * x + x * scr))
        return tuple(out)
    if kind == "LINEAR_LIGHT":
        return tuple(x + t * (2.0 * (y - 0.5)) if y > 0.5 else x + t * (2.0 * y - 1.0) for x, y in zip(a, b))
    return None  # HUE, SATURATION, VALUE, COLOR


@evaluates("mix_color")
def eval_mix_color(ev, e):
    t = ev.float(e.args["fac"])
    if e.props.get("clamp_factor", True):
        t = _clamp01(t)
    a, b = ev.color(e.args["a"]), ev.color(e.args["b"])
    kind = e.props.get("blend_type", "MIX")
    out = _blend(kind, t, a, b)
    if out is None:
        ev.approx(e, "blend mode %s approximated by MIX" % kind)
        out = _blend("MIX", t, a, b)
    if e.props.get("clamp_result"):
        out = tuple(_clamp01(x) for x in out)
    return out


@maps("ShaderNodeInvert")
def invert(ctx, node, socket):
    return Expr("invert", ctx.label(node), {
        "fac": ctx.input(node, "Fac", default=1.0),
        "color": ctx.input(node, "Color", default=(0.0, 0.0, 0.0))})


@evaluates("invert")
def eval_invert(ev, e):
    f = ev.float(e.args["fac"])
    c = ev.color(e.args["color"])
    return tuple((1.0 - f) * x + f * (1.0 - x) for x in c)


@maps("ShaderNodeValToRGB")
def color_ramp(ctx, node, socket):
    ramp = getattr(node, "color_ramp", None)
    elements = []
    for el in list(getattr(ramp, "elements", ()) or ()):
        col = tuple(float(x) for x in el.color)
        elements.append((float(el.position), col[:3], col[3] if len(col) > 3 else 1.0))
    elements.sort(key=lambda x: x[0])
    props = {"elements": elements,
             "interpolation": getattr(ramp, "interpolation", "LINEAR"),
             "color_mode": getattr(ramp, "color_mode", "RGB"),
             "output": getattr(socket, "identifier", "Color")}
    if elements and hasattr(ramp, "evaluate"):
        # Blender's own evaluation, as Cycles bakes it: every interpolation and colour mode.
        props["table"] = [tuple(float(x) for x in ramp.evaluate(i / (TABLE_SIZE - 1))) for i in range(TABLE_SIZE)]
    return Expr("color_ramp", ctx.label(node), {"fac": ctx.input(node, "Fac", default=0.5)}, props)


@evaluates("color_ramp")
def eval_color_ramp(ev, e):
    els = e.props.get("elements") or []
    alpha_out = e.props.get("output") == "Alpha"
    if not els:
        return 0.0 if alpha_out else (0.0, 0.0, 0.0)
    t = ev.float(e.args["fac"])
    interp = e.props.get("interpolation", "LINEAR")
    if e.props.get("table"):
        rgba = table_lookup(e.props["table"], t, interp != "CONSTANT")
        return float(rgba[3]) if alpha_out else tuple(rgba[:3])
    if interp not in ("LINEAR", "CONSTANT", "EASE"):
        ev.approx(e, "%s interpolation approximated as linear" % interp)
    if e.props.get("color_mode", "RGB") != "RGB":
        ev.approx(e, "%s colour mode approximated as RGB" % e.props.get("color_mode"))
    if t <= els[0][0]:
        rgb, a = els[0][1], els[0][2]
    elif t >= els[-1][0]:
        rgb, a = els[-1][1], els[-1][2]
    else:
        rgb, a = els[-1][1], els[-1][2]
        for (p0, c0, a0), (p1, c1, a1) in zip(els, els[1:]):
            if p0 <= t <= p1:
                if interp == "CONSTANT":
                    rgb, a = c0, a0
                    break
                f = (t - p0) / (p1 - p0) if p1 > p0 else 0.0
                if interp == "EASE":
                    f = f * f * (3.0 - 2.0 * f)
                rgb = tuple((1 - f) * x + f * y for x, y in zip(c0, c1))
                a = (1 - f) * a0 + f * a1
                break
    return float(a) if alpha_out else tuple(rgb)


@maps("ShaderNodeGamma")
def gamma(ctx, node, socket):
    return Expr("gamma", ctx.label(node), {"color": ctx.input(node, "Color", default=(1, 1, 1)),
                                           "gamma": ctx.input(node, "Gamma", default=1.0)})


@evaluates("gamma")
def eval_gamma(ev, e):
    g = ev.float(e.args["gamma"])
    return tuple(x ** g if x > 0.0 else x for x in ev.color(e.args["color"]))


@maps("ShaderNodeBrightContrast")
def bright_contrast(ctx, node, socket):
    return Expr("bright_contrast", ctx.label(node), {
        "color": ctx.input(node, "Color", default=(1, 1, 1)),
        "bright": ctx.input(node, "Bright", default=0.0),
        "contrast": ctx.input(node, "Contrast", default=0.0)})


@evaluates("bright_contrast")
def eval_bright_contrast(ev, e):
    bright, contrast = ev.float(e.args["bright"]), ev.float(e.args["contrast"])
    a = 1.0 + contrast
    b = bright - contrast * 0.5
    return tuple(max(a * x + b, 0.0) for x in ev.color(e.args["color"]))


@maps("ShaderNodeHueSaturation")
def hue_saturation(ctx, node, socket):
    return Expr("hue_saturation", ctx.label(node), {
        "color": ctx.input(node, "Color", default=(0.8, 0.8, 0.8)),
        "fac": ctx.input(node, "Fac", default=1.0),
        "hue": ctx.input(node, "Hue", default=0.5),
        "saturation": ctx.input(node, "Saturation", default=1.0),
        "value": ctx.input(node, "Value", default=1.0)})


@evaluates("hue_saturation")
def eval_hue_saturation(ev, e):
    import colorsys
    c = ev.color(e.args["color"])
    if "hue" not in e.args:
        return c
    h, s, v = colorsys.rgb_to_hsv(*[max(x, 0.0) for x in c])
    h = (h + ev.float(e.args["hue"]) + 0.5) % 1.0
    s = _clamp01(s * ev.float(e.args["saturation"]))
    v = v * ev.float(e.args["value"])
    out = colorsys.hsv_to_rgb(h, s, v)
    f = ev.float(e.args["fac"])
    return tuple(max((1 - f) * a + f * b, 0.0) for a, b in zip(c, out))


def _rgb_to_hsl(c):
    """Cycles' rgb_to_hsl."""
    hi, lo = max(c), min(c)
    lum = min(1.0, (hi + lo) / 2.0)
    if hi == lo:
        return (0.0, 0.0, lum)
    d = hi - lo
    s = d / (2.0 - hi - lo) if lum > 0.5 else d / (hi + lo)
    r, g, b = c
    if hi == r:
        h = (g - b) / d + (6.0 if g < b else 0.0)
    elif hi == g:
        h = (b - r) / d + 2.0
    else:
        h = (r - g) / d + 4.0
    return (h / 6.0, s, lum)


def _hsl_to_rgb(c):
    """Cycles' hsl_to_rgb."""
    h, s, lum = c
    rgb = (_clamp01(abs(h * 6.0 - 3.0) - 1.0), _clamp01(2.0 - abs(h * 6.0 - 2.0)), _clamp01(2.0 - abs(h * 6.0 - 4.0)))
    chroma = (1.0 - abs(2.0 * lum - 1.0)) * s
    return tuple((x - 0.5) * chroma + lum for x in rgb)


def _rgb_to_hsv(c):
    """Cycles' rgb_to_hsv (hue in [0, 1))."""
    hi, lo = max(c), min(c)
    d = hi - lo
    s = d / hi if hi != 0.0 else 0.0
    h = 0.0
    if s != 0.0:
        cc = tuple((hi - x) / d for x in c)
        h = cc[2] - cc[1] if c[0] == hi else (2.0 + cc[0] - cc[2] if c[1] == hi else 4.0 + cc[1] - cc[0])
        h /= 6.0
        if h < 0.0:
            h += 1.0
    return (h, s, hi)


def _hsv_to_rgb(c):
    """Cycles' hsv_to_rgb."""
    h, s, v = c
    if s == 0.0:
        return (v, v, v)
    h = 0.0 if h == 1.0 else h
    h *= 6.0
    i = math.floor(h)
    f = h - i
    p, q, t = v * (1.0 - s), v * (1.0 - s * f), v * (1.0 - s * (1.0 - f))
    return {0: (v, t, p), 1: (q, v, p), 2: (p, v, t), 3: (p, q, v), 4: (t, p, v)}.get(int(i), (v, p, q))


COLOR_SPACES = {"RGB_TO_HSV": _rgb_to_hsv, "HSV_TO_RGB": _hsv_to_rgb, "RGB_TO_HSL": _rgb_to_hsl,
                "HSL_TO_RGB": _hsl_to_rgb}


@evaluates("color_space")
def eval_color_space(ev, e):
    try:
        out = COLOR_SPACES[e.props["convert"]](ev.color(e.args["color"]))
    except (ZeroDivisionError, ValueError, OverflowError):
        return (0.0, 0.0, 0.0)
    return out if all(math.isfinite(x) for x in out) else (0.0, 0.0, 0.0)


@maps("ShaderNodeSeparateColor", "ShaderNodeSeparateRGB", "ShaderNodeSeparateXYZ", "ShaderNodeSeparateHSV")
def separate(ctx, node, socket):
    ident = getattr(socket, "identifier", "Red")
    index = {"Red": 0, "R": 0, "X": 0, "H": 0, "Green": 1, "G": 1, "Y": 1, "S": 1, "Blue": 2, "B": 2, "Z": 2,
             "V": 2}.get(ident, 0)
    mode = "HSV" if getattr(node, "bl_idname", "") == "ShaderNodeSeparateHSV" else getattr(node, "mode", "RGB")
    src = ctx.input(node, "Color", "Image", "Vector", default=(0, 0, 0))
    if mode in ("HSV", "HSL"):  # the colour converted first, as Cycles' svm_separate_color
        src = Expr("color_space", ctx.label(node), {"color": src}, {"convert": "RGB_TO_" + mode})
    return Expr("separate", ctx.label(node), {"value": src}, {"index": index})


@evaluates("separate")
def eval_separate(ev, e):
    return float(ev.color(e.args["value"])[e.props["index"]])


@maps("ShaderNodeCombineColor", "ShaderNodeCombineRGB", "ShaderNodeCombineXYZ", "ShaderNodeCombineHSV")
def combine(ctx, node, socket):
    mode = "HSV" if getattr(node, "bl_idname", "") == "ShaderNodeCombineHSV" else getattr(node, "mode", "RGB")
    out = Expr("combine", ctx.label(node), {
        "x": ctx.input(node, "Red", "R", "X", "H", default=0.0),
        "y": ctx.input(node, "Green", "G", "Y", "S", default=0.0),
        "z": ctx.input(node, "Blue", "B", "Z", "V", default=0.0)})
    if mode in ("HSV", "HSL"):
        out = Expr("color_space", ctx.label(node), {"color": out}, {"convert": mode + "_TO_RGB"})
    return out


@evaluates("combine")
def eval_combine(ev, e):
    return (ev.float(e.args["x"]), ev.float(e.args["y"]), ev.float(e.args["z"]))


@maps("ShaderNodeRGBToBW")
def rgb_to_bw(ctx, node, socket):
    return Expr("to_float", ctx.label(node), {"value": ctx.input(node, "Color", default=(0.5, 0.5, 0.5))},
                {"from": "RGBA"})


__all__ = ["Const"]


# ---- Lookup tables as Cycles bakes them (its blender/util.h): RGB / Vector / Float Curves and
# Color Ramps become 256 values of Blender's own evaluation (CurveMapping.evaluate,
# ColorRamp.evaluate), looked up with linear interpolation (the ramp's Constant mode without),
# so every handle type, interpolation and colour mode is Blender's.
TABLE_SIZE = 256  # Cycles' RAMP_TABLE_SIZE


def _curve_range(mapping, n):
    """The x range of the first n curves' points (Cycles' curvemapping_minmax)."""
    lo, hi = float("inf"), float("-inf")
    for curve in list(mapping.curves)[:n]:
        points = list(curve.points)
        if points:
            lo, hi = min(lo, float(points[0].location[0])), max(hi, float(points[-1].location[0]))
    return (lo, hi) if lo < hi else (0.0, 1.0)


def curve_table(mapping, kind):
    """kind 'rgb' (R, G, B of the combined C curve), 'vector' (X, Y, Z) or 'float': (table,
    min_x, max_x, extrapolate); None when the mapping cannot be evaluated (no Blender)."""
    if mapping is None or not hasattr(mapping, "evaluate"):
        return None
    if hasattr(mapping, "initialize"):
        mapping.initialize()  # the curves' evaluation tables (evaluate needs them)
    mapping.update()
    curves = list(mapping.curves)
    n = {"rgb": 4, "vector": 3, "float": 1}[kind]
    lo, hi = _curve_range(mapping, n)
    ev = mapping.evaluate
    table = []
    for i in range(TABLE_SIZE):
        t = lo + i / (TABLE_SIZE - 1) * (hi - lo)
        if kind == "rgb":
            c = ev(curves[3], t)
            table.append((ev(curves[0], c), ev(curves[1], c), ev(curves[2], c)))
        elif kind == "vector":
            table.append((ev(curves[0], t), ev(curves[1], t), ev(curves[2], t)))
        else:
            table.append(ev(curves[0], t))
    return table, lo, hi, getattr(mapping, "extend", "EXTRAPOLATED") == "EXTRAPOLATED"


def table_lookup(table, f, interpolate=True, extrapolate=False):
    """Cycles' rgb_ramp_lookup / float_ramp_lookup: entry i at f = i / (size - 1)."""
    n = len(table)
    if extrapolate and (f < 0.0 or f > 1.0):
        t0, t1, d = (table[0], table[1], -f) if f < 0.0 else (table[-1], table[-2], f - 1.0)
        if isinstance(t0, float):
            return t0 + (t0 - t1) * d * (n - 1)
        return tuple(a + (a - b) * d * (n - 1) for a, b in zip(t0, t1))
    f = min(max(f, 0.0), 1.0) * (n - 1) if f == f else 0.0
    i = min(max(int(f), 0), n - 1)
    t = f - i
    a = table[i]
    if interpolate and t > 0.0:
        b = table[i + 1]
        return (1.0 - t) * a + t * b if isinstance(a, float) else tuple((1.0 - t) * x + t * y for x, y in zip(a, b))
    return a


@maps("ShaderNodeRGBCurve", "ShaderNodeVectorCurve", "ShaderNodeFloatCurve")
def curves(ctx, node, socket):
    idname = getattr(node, "bl_idname", "")
    kind = {"ShaderNodeRGBCurve": "rgb", "ShaderNodeVectorCurve": "vector"}.get(idname, "float")
    value = {"rgb": ("Color", (0.5, 0.5, 0.5)), "vector": ("Vector", (0.0, 0.0, 0.0)), "float": ("Value", 1.0)}[kind]
    baked = curve_table(getattr(node, "mapping", None), kind)
    if baked is None:
        ctx.warn(node, "its curve could not be read: passed through unchanged")
        return ctx.input(node, value[0], default=value[1])
    table, lo, hi, extrapolate = baked
    return Expr("curves", ctx.label(node), {"fac": ctx.input(node, "Fac", "Factor", default=1.0),
                                            "value": ctx.input(node, value[0], default=value[1])},
                {"kind": kind, "table": table, "min_x": lo, "max_x": hi, "extrapolate": extrapolate})


@evaluates("curves")
def eval_curves(ev, e):
    fac, table = ev.float(e.args["fac"]), e.props["table"]
    lo, hi, extrapolate = e.props["min_x"], e.props["max_x"], e.props["extrapolate"]
    if e.props["kind"] == "float":
        v = ev.float(e.args["value"])
        return (1.0 - fac) * v + fac * table_lookup(table, (v - lo) / (hi - lo), True, extrapolate)
    c = ev.color(e.args["value"])
    mapped = [table_lookup(table, (x - lo) / (hi - lo), True, extrapolate)[k] for k, x in enumerate(c)]
    return tuple((1.0 - fac) * x + fac * m for x, m in zip(c, mapped))


@maps("ShaderNodeBlackbody")
def blackbody(ctx, node, socket):
    return Expr("blackbody", ctx.label(node), {"temperature": ctx.input(node, "Temperature", default=1500.0)})


@maps("ShaderNodeWavelength")
def wavelength(ctx, node, socket):
    return Expr("wavelength", ctx.label(node), {"wavelength": ctx.input(node, "Wavelength", default=500.0)})


@evaluates("wavelength")
def eval_wavelength(ev, e):
    # Exported as an engine node (Cycles' CIE table and scale live there).
    ev.approx(e, "wavelength colour approximated as grey without the engine")
    return (0.5, 0.5, 0.5)


@evaluates("blackbody")
def eval_blackbody(ev, e):
    # Folds only with the engine's table (a constant temperature is exported as a node).
    ev.approx(e, "blackbody colour approximated as white without the engine")
    return (1.0, 1.0, 1.0)
