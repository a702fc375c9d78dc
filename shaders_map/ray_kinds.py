"""Light Path's ray-type outputs (Is Camera Ray, Is Shadow Ray, ...) in a material or the world.

Cycles evaluates a shader for each ray with that ray's flags, so Mix Shader (Fac = Is Camera
Ray) shows one shader to the camera and another to everything else. The engine's materials do
not know the ray that reached them; its geometry does (ray visibility, docs/scene-format.md).
So a material that reads a ray type is lowered once per kind of ray the engine tells apart,
with the outputs made constants, and the exporter sends the object once per group of kinds
that see the same material, each copy visible to its group alone. A kind's rays meet only
their own copy: exact wherever Cycles' flags are a function of the engine's kind.

The engine's kinds and the Cycles path flags their rays carry (Cycles 3.4, path_state_next):
a transmission ray is a refraction (glossy, singular when smooth) or a translucency (diffuse),
a glossy reflection may be singular: a material telling those apart by Is Glossy / Is Diffuse /
Is Singular cannot be split exactly (its first reading is used, with a warning). Volume
scattering rays meet what diffuse rays meet (scene/ray_visibility.h), so they see the diffuse
kind's copy.

The world: Cycles evaluates it for next-event estimation with no ray flags and for a ray that
escapes with the ray's, so only Is Camera Ray (camera rays see it, no other ray does) and Is
Shadow Ray (0: shadow rays never see the world) have one value per kind; the engine's world
takes a look of its own for camera rays (world "camera").

"""

from .evaluate import Evaluator, is_constant
from .ir import Const, Expr, Closure
from .issues import Issues

# Light Path's outputs that read the ray's flags, and the flag each reads.
FLAG_OUTPUTS = {"Is Camera Ray": "camera", "Is Shadow Ray": "shadow", "Is Diffuse Ray": "diffuse",
                "Is Glossy Ray": "glossy", "Is Singular Ray": "singular", "Is Reflection Ray": "reflect",
                "Is Transmission Ray": "transmit", "Is Volume Scatter Ray": "volume_scatter"}

# The engine's ray kinds (its "visibility" keys) and the flag sets of the rays of each kind.
KINDS = ("camera", "diffuse", "glossy", "transmission", "shadow", "volume_scatter")
KIND_FLAGS = {
    "camera": ({"camera"},),
    "diffuse": ({"diffuse", "reflect"},),
    "glossy": ({"glossy", "reflect"}, {"glossy", "reflect", "singular"}),
    "transmission": ({"glossy", "transmit"}, {"glossy", "transmit", "singular"}, {"diffuse", "transmit"}),
    "shadow": ({"shadow"},),
    "volume_scatter": ({"volume_scatter"},),
}


def _children(ir):
    if isinstance(ir, Expr):
        return list(ir.args.values())
    if isinstance(ir, Closure):
        return list(ir.params.values()) + list(ir.children)
    return []


def walk(roots):
    """Each node of these IR trees once."""
    seen, stack = set(), [r for r in roots if r is not None]
    while stack:
        x = stack.pop()
        if id(x) in seen:
            continue
        seen.add(id(x))
        yield x
        stack.extend(c for c in _children(x) if c is not None)


def flag_outputs(*roots):
    """The Light Path flag outputs (FLAG_OUTPUTS' keys) these IR trees read."""
    return {x.props["output"] for x in walk(roots)
            if isinstance(x, Expr) and x.op == "light_path" and x.props.get("output") in FLAG_OUTPUTS}


def substitute(ir, flags, memo=None):
    """A copy of ir with each Light Path flag output the constant it has on a ray carrying
    `flags` (replace_leaves)."""
    def flag(e):
        if e.op == "light_path" and e.props.get("output") in FLAG_OUTPUTS:
            return Const(1.0 if FLAG_OUTPUTS[e.props["output"]] in flags else 0.0)
        return None
    return replace_leaves(ir, flag, memo, collapse_mixes=True)


def replace_leaves(ir, leaf, memo=None, collapse_mixes=False):
    """A copy of ir with each expression e for which leaf(e) is not None replaced by it; with
    collapse_mixes, each Mix Shader whose factor became a constant 0 or 1 replaced by the shader
    it picks (Cycles clamps the factor to [0, 1]; only once no ray flag is left in the factor:
    the evaluator reads a flag as one ray's)."""
    memo = {} if memo is None else memo
    if ir is None or isinstance(ir, Const):
        return ir
    key = id(ir)
    if key in memo:
        return memo[key]
    if isinstance(ir, Expr):
        out = leaf(ir)
        if out is None:
            out = Expr(ir.op, ir.node, {k: replace_leaves(v, leaf, memo, collapse_mixes) for k, v in ir.args.items()},
                       ir.props)
    elif isinstance(ir, Closure):
        params = {k: replace_leaves(v, leaf, memo, collapse_mixes) for k, v in ir.params.items()}
        children = [replace_leaves(c, leaf, memo, collapse_mixes) for c in ir.children]
        out = Closure(ir.kind, ir.node, params, children, ir.props)
        fac = params.get("fac")
        if collapse_mixes and ir.kind == "mix" and fac is not None and is_constant(fac):
            f = Evaluator(Issues()).float(fac)
            if f <= 0.0 or f >= 1.0:
                out = (children + [None, None])[0 if f <= 0.0 else 1]
    else:
        out = ir
    memo[key] = out
    return out


def kind_variants(lower, issues, label):
    """Groups the engine's ray kinds by the material each sees. lower(flags) -> engine params
    of the material on a ray with those flags. Returns [(kinds, params)], in KINDS' order of
    each group's first kind; one group: the material does not depend on the ray's kind."""
    import json
    by_kind = {}
    for kind in KINDS:
        readings = [lower(flags) for flags in KIND_FLAGS[kind]]
        texts = [json.dumps(r, sort_keys=True) for r in readings]
        if len(set(texts)) > 1:
            issues.add(label, "%s rays are refractions, translucency or singular reflections alike to the engine; "
                              "shaded here as the first (Is Glossy / Is Diffuse / Is Singular Ray tell them apart)"
                       % kind)
        by_kind[kind] = (texts[0], readings[0])
    if by_kind["volume_scatter"][0] != by_kind["diffuse"][0]:
        issues.add(label, "volume scattering rays see what diffuse rays see (Cycles' ray visibility does the same)")
        by_kind["volume_scatter"] = by_kind["diffuse"]
    groups = []
    for kind in KINDS:
        text, params = by_kind[kind]
        for g in groups:
            if g[0] == text:
                g[1].append(kind)
                break
        else:
            groups.append((text, [kind], params))
    return [(kinds, params) for _, kinds, params in groups]


def lighting_look(variants):
    """Of kind_variants-style [(kinds or None, x)], the x diffuse rays see (the look that stands
    for the material where one look must do)."""
    return next(x for kinds, x in variants if kinds is None or "diffuse" in kinds)
