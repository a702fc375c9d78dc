"""Lowering: the engine-neutral description -> what the engine's materials accept today.

This is the ONE place that knows the engine's material types.  Today the engine takes
``diffuse`` {color}, ``emission`` {color, strength} and ``glossy`` {color, roughness},
diffuse/glossy with optional ``emission``/``emission_strength``;
when it gains Principled, glass, textures, ... only this module changes.

A closure tree is flattened into weighted lobes (Mix/Add are linear), lobes of one type
are summed exactly, and when several types remain the dominant one is kept.  Every node
that could not be represented exactly is recorded, and the caller gets ONE warning per
material naming those nodes.
"""

from .ir import Const, Closure
from .evaluate import Evaluator, is_constant
from .graph import LUMINANCE

ENGINE_TYPES = ("diffuse", "emission", "glossy")

DEFAULT_SURFACE = {"type": "diffuse", "color": [0.8, 0.8, 0.8]}


def luminance(c):
    return LUMINANCE[0] * c[0] + LUMINANCE[1] * c[1] + LUMINANCE[2] * c[2]


def _scale(c, w):
    return tuple(x * y for x, y in zip(c, w))


def _clamp01(x):
    return 0.0 if x < 0.0 else 1.0 if x > 1.0 else x


class Lobe:
    __slots__ = ("type", "color", "roughness", "node")

    def __init__(self, type_, color, node, roughness=None):
        self.type = type_
        self.color = tuple(float(x) for x in color)
        self.node = node
        self.roughness = roughness


class _Lowerer:
    def __init__(self, evaluator, context):
        self.ev = evaluator
        self.issues = evaluator.issues
        self.context = context  # "surface" or "world"

    def approx(self, node, reason):
        self.issues.add(node, reason)

    def _normal(self, c):
        n = c.params.get("normal")
        if n is not None and not isinstance(n, Const) and not is_constant(n):
            self.ev.value(n)  # records the Normal Map / Bump node as approximated
            self.approx(c.node, "normal input ignored")

    def collect(self, c, w, out, depth=0):
        if c is None or depth > 200:
            return
        if max(w) <= 0.0:
            return
        k = c.kind
        ev = self.ev
        if k == "mix":
            f = _clamp01(ev.float(c.params.get("fac", Const(0.5))))
            a, b = (c.children + [None, None])[:2]
            self.collect(a, tuple(x * (1.0 - f) for x in w), out, depth + 1)
            self.collect(b, tuple(x * f for x in w), out, depth + 1)
        elif k == "add":
            for ch in c.children:
                self.collect(ch, w, out, depth + 1)
        elif k in ("emission", "background"):
            col = _scale(ev.color(c.params["color"]), w)
            s = ev.float(c.params.get("strength", Const(1.0)))
            if k == "background" and self.context == "surface":
                self.approx(c.node, "Background shader in a material treated as emission")
            if k == "emission" and self.context == "world":
                pass  # Cycles treats an emission on the world output like a background
            out.append(Lobe("emission", _scale(col, (s, s, s)), c.node))
        elif k == "diffuse":
            self._normal(c)
            r = c.params.get("roughness")
            if r is not None and ev.float(r) > 0.0:
                self.approx(c.node, "Oren-Nayar roughness ignored")
            out.append(Lobe("diffuse", _scale(ev.color(c.params["color"]), w), c.node))
        elif k in ("glossy", "anisotropic"):
            self._normal(c)
            dist = c.props.get("distribution", "GGX")
            if dist not in ("GGX", "MULTI_GGX"):
                self.approx(c.node, "%s distribution approximated as GGX" % dist)
            an = c.params.get("anisotropy")
            if an is not None and abs(ev.float(an)) > 1e-6:
                self.approx(c.node, "anisotropy ignored")
            out.append(Lobe("glossy", _scale(ev.color(c.params["color"]), w), c.node,
                            _clamp01(ev.float(c.params.get("roughness", Const(0.5))))))
        elif k == "principled":
            self._principled(c, w, out)
        elif k in ("glass", "refraction", "translucent"):
            self._normal(c)
            self.approx(c.node, "%s not supported by the engine yet, shown as diffuse" % k)
            out.append(Lobe("diffuse", _scale(ev.color(c.params["color"]), w), c.node))
        elif k == "transparent":
            self.approx(c.node, "transparency not supported by the engine yet, ignored")
            out.append(Lobe("transparent", _scale(ev.color(c.params["color"]), w), c.node))
        elif k == "holdout":
            self.approx(c.node, "holdout not supported by the engine yet, ignored")
        elif k == "unsupported":
            self.approx(c.node, "unsupported shader %s, shown as diffuse" % c.props.get("bl_idname", "?"))
            out.append(Lobe("diffuse", _scale(ev.color(c.params["color"]), w), c.node))
        else:
            self.approx(c.node, "unknown closure '%s' ignored" % k)

    def _principled(self, c, w, out):
        ev = self.ev
        p = c.params
        f = lambda key: ev.float(p[key])  # noqa: E731
        self._normal(c)
        base = ev.color(p["base_color"])
        metallic = _clamp01(f("metallic"))
        transmission = _clamp01(f("transmission"))
        rough = _clamp01(f("roughness"))
        dropped = []
        for key, label in (("specular", "specular"), ("subsurface", "subsurface"), ("sheen", "sheen"),
                           ("clearcoat", "clearcoat")):
            if f(key) > 0.0 and (key != "specular" or metallic < 1.0):
                dropped.append(label)
        if transmission > 0.0 and metallic < 1.0:
            dropped.append("transmission")
        if f("alpha") < 1.0:
            dropped.append("alpha")
        if f("anisotropic") > 0.0 and metallic > 0.0:
            dropped.append("anisotropy")
        if dropped:
            self.approx(c.node, "approximated as diffuse + metal; %s dropped" % "/".join(dropped))
        dw = (1.0 - metallic) * (1.0 - transmission)
        if dw > 0.0:
            out.append(Lobe("diffuse", _scale(base, tuple(x * dw for x in w)), c.node))
        if metallic > 0.0:
            out.append(Lobe("glossy", _scale(base, tuple(x * metallic for x in w)), c.node, rough))
        if transmission > 0.0 and metallic < 1.0:
            tw = (1.0 - metallic) * transmission
            out.append(Lobe("diffuse", _scale(base, tuple(x * tw for x in w)), c.node))
        em = _scale(ev.color(p["emission"]), w)
        s = f("emission_strength")
        if max(em) > 0.0 and s > 0.0:
            out.append(Lobe("emission", _scale(em, (s, s, s)), c.node))


def _emission_params(radiance):
    m = max(radiance)
    if m <= 0.0:
        return [0.0, 0.0, 0.0], 0.0
    return [x / m for x in radiance], m


def _combine(lobes, issues, owner_default):
    by_type = {}
    for lobe in lobes:
        if max(lobe.color) <= 0.0 and lobe.type != "transparent":
            continue
        by_type.setdefault(lobe.type, []).append(lobe)
    if "transparent" in by_type and len(by_type) > 1:
        del by_type["transparent"]
    elif "transparent" in by_type:
        by_type = {"diffuse": by_type.pop("transparent")}
    if not by_type:
        return owner_default

    def weight(t):
        return sum(luminance(lobe.color) for lobe in by_type[t])

    # Emission rides along on diffuse/glossy ("emission" key); only scattering types compete.
    emission = by_type.pop("emission", None)
    emitted = [sum(lobe.color[i] for lobe in emission) for i in range(3)] if emission else None
    if not by_type:
        col, strength = _emission_params(emitted)
        return {"type": "emission", "color": col, "strength": strength}
    chosen = max(by_type, key=lambda t: (weight(t), t == "diffuse"))
    for t, ls in by_type.items():
        if t != chosen:
            for lobe in ls:
                issues.add(lobe.node, "%s part dropped (the engine material is %s only)" % (t, chosen))
    ls = by_type[chosen]
    color = [sum(lobe.color[i] for lobe in ls) for i in range(3)]
    if chosen == "glossy":
        wsum = sum(max(luminance(lobe.color), 1e-9) for lobe in ls)
        rough = sum(lobe.roughness * max(luminance(lobe.color), 1e-9) for lobe in ls) / wsum
        if max(lobe.roughness for lobe in ls) - min(lobe.roughness for lobe in ls) > 1e-3:
            for lobe in ls:
                issues.add(lobe.node, "roughness averaged with other glossy parts")
        params = {"type": "glossy", "color": color, "roughness": rough}
    else:
        params = {"type": "diffuse", "color": color}
    if emitted is not None:
        col, strength = _emission_params(emitted)
        params["emission"] = col
        params["emission_strength"] = strength
    return params


def lower_surface(desc, image_average=None):
    """MaterialDescription -> (engine params dict, Issues)."""
    ev = Evaluator(desc.issues, image_average)
    low = _Lowerer(ev, "surface")
    if desc.surface is None:
        params = {"type": "diffuse", "color": [0.0, 0.0, 0.0]}  # Cycles: no closure = black
    else:
        lobes = []
        low.collect(desc.surface, (1.0, 1.0, 1.0), lobes)
        params = _combine(lobes, desc.issues, {"type": "diffuse", "color": [0.0, 0.0, 0.0]})
    if desc.volume is not None:
        desc.issues.add(desc.volume.node if hasattr(desc.volume, "node") else "Volume",
                        "volume shader not supported by the engine yet, ignored")
    if desc.displacement_linked:
        desc.issues.add(desc.output_label, "displacement ignored")
    return params, desc.issues


def lower_world(desc, image_average=None):
    """WorldDescription -> ({"color": [...], "strength": s}, Issues)."""
    ev = Evaluator(desc.issues, image_average)
    low = _Lowerer(ev, "world")
    lobes = []
    if desc.surface is not None:
        low.collect(desc.surface, (1.0, 1.0, 1.0), lobes)
    radiance = [0.0, 0.0, 0.0]
    for lobe in lobes:
        if lobe.type == "emission":
            radiance = [a + b for a, b in zip(radiance, lobe.color)]
        else:
            desc.issues.add(lobe.node, "%s shader on the world ignored" % lobe.type)
    if desc.volume is not None:
        desc.issues.add(getattr(desc.volume, "node", "Volume"), "world volume not supported yet, ignored")
    m = max(radiance)
    if m > 1.0:
        return {"color": [x / m for x in radiance], "strength": m}, desc.issues
    return {"color": radiance, "strength": 1.0}, desc.issues
