"""Render passes: which ones a view layer asks for (Blender's own view_layer.use_pass_*
and Cycles' view_layer.cycles.use_pass_volume_*), registering them with Blender
(RenderEngine.update_render_passes, so the compositor's Render Layers node and multilayer
EXR have them) and which engine pass fills each (engine/include/rendezvous.h, rdv_pass).

Cycles' light passes need the session setting "light_passes" (every integrator classifies
its paths: path, bdpt, the Metropolis integrators and auto's pick). BDPT's strategy passes (view_layer.rendezvous.use_pass_strategies) need
"strategy_passes"; other integrators have no strategies: a warning, and black passes."""

from .. import binding

# (Blender pass name, view layer property, where it lives, engine pass, channels, chan_id, type)
# where: "layer" = view_layer, "cycles" = view_layer.cycles, "rendezvous" = scene.rendezvous
_DATA_PASSES = [
    ("Depth", "use_pass_z", "layer", binding.PASS_DEPTH, 1, "Z", "VALUE"),
    ("Normal", "use_pass_normal", "layer", binding.PASS_NORMAL, 3, "XYZ", "VECTOR"),
    ("Mist", "use_pass_mist", "layer", binding.PASS_MIST, 1, "Z", "VALUE"),
    ("IndexOB", "use_pass_object_index", "layer", binding.PASS_OBJECT_INDEX, 1, "X", "VALUE"),
    ("IndexMA", "use_pass_material_index", "layer", binding.PASS_MATERIAL_INDEX, 1, "X", "VALUE"),
    # View Layer > Passes > Data > Denoising Data (Cycles' property; its Data panel shows it
    # for us): the three passes Cycles registers, which Blender's Denoise node takes.
    ("Denoising Normal", "denoising_store_passes", "cycles", binding.PASS_DENOISING_NORMAL, 3, "XYZ", "VECTOR"),
    ("Denoising Albedo", "denoising_store_passes", "cycles", binding.PASS_DENOISING_ALBEDO, 3, "RGB", "COLOR"),
    ("Denoising Depth", "denoising_store_passes", "cycles", binding.PASS_DENOISING_DEPTH, 1, "Z", "VALUE"),
    # View Layer > Passes > Light > Other > Shadow Catcher (Cycles' property): the catcher's
    # shadows and light as a factor; Combined is then the matte (session "shadow_catcher_pass").
    ("Shadow Catcher", "use_pass_shadow_catcher", "cycles", binding.PASS_SHADOW_CATCHER, 3, "RGB", "COLOR"),
]
LIGHT_PASSES = [
    ("Emit", "use_pass_emit", "layer", binding.PASS_EMISSION),
    ("Env", "use_pass_environment", "layer", binding.PASS_ENVIRONMENT),
    ("DiffDir", "use_pass_diffuse_direct", "layer", binding.PASS_DIFFUSE_DIRECT),
    ("DiffInd", "use_pass_diffuse_indirect", "layer", binding.PASS_DIFFUSE_INDIRECT),
    ("GlossDir", "use_pass_glossy_direct", "layer", binding.PASS_GLOSSY_DIRECT),
    ("GlossInd", "use_pass_glossy_indirect", "layer", binding.PASS_GLOSSY_INDIRECT),
    ("GlossCol", "use_pass_glossy_color", "layer", binding.PASS_GLOSSY_COLOR),
    ("TransDir", "use_pass_transmission_direct", "layer", binding.PASS_TRANSMISSION_DIRECT),
    ("TransInd", "use_pass_transmission_indirect", "layer", binding.PASS_TRANSMISSION_INDIRECT),
    ("TransCol", "use_pass_transmission_color", "layer", binding.PASS_TRANSMISSION_COLOR),
    ("VolumeDir", "use_pass_volume_direct", "cycles", binding.PASS_VOLUME_DIRECT),
    ("VolumeInd", "use_pass_volume_indirect", "cycles", binding.PASS_VOLUME_INDIRECT),
]


def strategy_passes(max_depth):
    """[(Blender pass name, engine pass)] of BDPT's strategy passes of paths up to max_depth
    bounces, numbered as engine/src/film/strategy_passes.h: depth-major (depth 0: s = 0,
    t = 2; depth d: s = 0 .. d + 1, t = d + 2 - s), then the longer paths' rest."""
    names = ["Strategy_s0t2"]
    for depth in range(1, max_depth + 1):
        names += ["Strategy_s%dt%d" % (s, depth + 2 - s) for s in range(depth + 2)]
    names.append("Strategy_rest")
    return [(name, binding.PASS_STRATEGY_FIRST + k) for k, name in enumerate(names)]


def wanted_strategy_depth(layer):
    """The view layer's strategy depth when it asks for the strategy passes, else None."""
    props = getattr(layer, "rendezvous", None)
    if props is None or not getattr(props, "use_pass_strategies", False):
        return None
    return int(props.strategy_max_depth)


def _flag(layer, scene, prop, where):
    if where == "cycles":
        owner = getattr(layer, "cycles", None)
    elif where == "rendezvous":
        owner = getattr(scene, "rendezvous", None)
    else:
        owner = layer
    return bool(owner is not None and getattr(owner, prop, False))


def wants_light_passes(layer, scene=None):
    """Whether the view layer asks for any of Cycles' light passes. Diffuse Color alone does
    not: without them it is the first hit's albedo (as before), with them Cycles' diffuse
    colour that Diffuse Direct / Indirect divide by."""
    return any(_flag(layer, scene, prop, where) for _, prop, where, _ in LIGHT_PASSES)


def shader_aovs(layer, warn=None):
    """[(name, "color" | "value")] of the view layer's Shader AOVs (View Layer > Passes > Shader
    AOV), in its order: the valid ones (Blender marks a name used twice or by a built-in pass
    invalid), at most the engine's MAX_SHADER_AOVS (the rest named in a warning)."""
    out = []
    for aov in getattr(layer, "aovs", ()):
        if not getattr(aov, "is_valid", True) or not aov.name:
            continue
        if len(out) == binding.MAX_SHADER_AOVS:
            if warn:
                warn("Passes: Shader AOV '%s' and those after it left out (at most %d)" % (aov.name, binding.MAX_SHADER_AOVS))
            break
        out.append((aov.name, "value" if aov.type == "VALUE" else "color"))
    return out


# View Layer > Passes > Cryptomatte: (Blender's pass prefix, view layer property, setting key).
CRYPTOMATTE_KINDS = [("CryptoObject", "use_pass_cryptomatte_object", "object"),
                     ("CryptoMaterial", "use_pass_cryptomatte_material", "material"),
                     ("CryptoAsset", "use_pass_cryptomatte_asset", "asset")]


def wants_cryptomatte(layer):
    return any(getattr(layer, prop, False) for _, prop, _ in CRYPTOMATTE_KINDS)


def cryptomatte_passes(layer):
    """[(Blender pass name, engine pass)] of the layer's Cryptomatte passes, as Cycles registers
    them: ceil(Levels / 2) RGBA passes per kind (CryptoObject00, CryptoObject01, ...), each two
    ranks of (id, coverage)."""
    count = (min(16, max(1, int(getattr(layer, "pass_cryptomatte_depth", 6)))) + 1) // 2
    out = []
    for kind, (prefix, prop, _) in enumerate(CRYPTOMATTE_KINDS):
        if getattr(layer, prop, False):
            first = binding.PASS_CRYPTOMATTE_FIRST + binding.CRYPTO_PASSES_PER_KIND * kind
            out += [("%s%02d" % (prefix, k), first + k) for k in range(count)]
    return out


def enabled_passes(layer, scene):
    """[(Blender name, engine pass, channels, chan_id, type)] the layer renders, Combined first."""
    out = [("Combined", binding.PASS_COMBINED, 4, "RGBA", "COLOR")]
    for name, prop, where, engine_pass, channels, chan_id, kind in _DATA_PASSES:
        if _flag(layer, scene, prop, where):
            out.append((name, engine_pass, channels, chan_id, kind))
    light = wants_light_passes(layer, scene)
    if _flag(layer, scene, "use_pass_diffuse_color", "layer"):
        # Cycles' Diffuse Color (what Diffuse Direct / Indirect divide by) with light passes;
        # else the first hit's albedo, as before.
        out.append(("DiffCol", binding.PASS_DIFFUSE_COLOR if light else binding.PASS_ALBEDO, 3, "RGB", "COLOR"))
    for name, prop, where, engine_pass in LIGHT_PASSES:
        if _flag(layer, scene, prop, where):
            out.append((name, engine_pass, 3, "RGB", "COLOR"))
    if _flag(layer, scene, "use_pass_noise", "rendezvous"):
        out.append(("Noise", binding.PASS_NOISE, 1, "X", "VALUE"))
    depth = wanted_strategy_depth(layer)
    if depth is not None:
        out += [(name, engine_pass, 3, "RGB", "COLOR") for name, engine_pass in strategy_passes(depth)]
    for k, (name, kind) in enumerate(shader_aovs(layer)):  # as Cycles registers them
        if kind == "color":
            out.append((name, binding.PASS_AOV_COLOR_FIRST + k, 4, "RGBA", "COLOR"))
        else:
            out.append((name, binding.PASS_AOV_VALUE_FIRST + k, 1, "X", "VALUE"))
    out += [(name, engine_pass, 4, "RGBA", "COLOR") for name, engine_pass in cryptomatte_passes(layer)]
    return out


def register_passes(engine, scene, layer):
    if scene is None or layer is None:
        return
    for name, _, channels, chan_id, kind in enabled_passes(layer, scene):
        engine.register_pass(scene, layer, name, channels, chan_id, kind)


def light_pass_settings(layer, scene, integrator, warn=print):
    """The session settings the layer's passes need: light passes ({} without any), BDPT's
    strategy passes, the denoising data, the Shadow Catcher pass, the Shader AOVs, Cryptomatte, and
    View Layer > Passes > Alpha Threshold, which the Object and Material Index and the AOVs use."""
    threshold = getattr(layer, "pass_alpha_threshold", None)
    data = {"pass_alpha_threshold": float(threshold)} if threshold is not None else {}
    if _flag(layer, scene, "denoising_store_passes", "cycles"):
        data["denoising_passes"] = True
    if _flag(layer, scene, "use_pass_shadow_catcher", "cycles"):
        data["shadow_catcher_pass"] = True  # Combined: the matte, as Cycles (else the shadow is in it)
    aovs = shader_aovs(layer, warn)
    if aovs:
        data["aovs"] = [{"name": name, "type": kind} for name, kind in aovs]
    if wants_cryptomatte(layer):  # the layer's name goes into the passes' metadata, as Cycles'
        data["cryptomatte"] = dict({key: bool(getattr(layer, prop, False)) for _, prop, key in CRYPTOMATTE_KINDS},
                                   levels=min(16, max(1, int(getattr(layer, "pass_cryptomatte_depth", 6)))),
                                   view_layer=layer.name)
    depth = wanted_strategy_depth(layer)
    if depth is not None:
        if integrator == "bdpt":
            data.update(strategy_passes=True, strategy_passes_max_depth=depth)
        else:
            warn("Passes: the BDPT strategy passes are the Bidirectional integrator's strategies; with %s they "
                 "stay black" % integrator)
    if not wants_light_passes(layer, scene):
        return data
    return dict(data, light_passes=True)
