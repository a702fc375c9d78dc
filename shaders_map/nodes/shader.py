"""Shader combinators and non-BSDF closures: Mix, Add, Emission, Background, Holdout."""

from ..ir import Closure, Const
from ..registry import maps


@maps("ShaderNodeMixShader")
def mix_shader(ctx, node, socket):
    inputs = list(getattr(node, "inputs", ()))
    fac = ctx.input(node, "Fac", default=0.5)
    shaders = [s for s in inputs if getattr(s, "type", "") == "SHADER"]
    a = ctx.eval_input(node, shaders[0]) if len(shaders) > 0 else None
    b = ctx.eval_input(node, shaders[1]) if len(shaders) > 1 else None
    return Closure("mix", ctx.label(node), {"fac": fac}, children=[a, b])


@maps("ShaderNodeAddShader")
def add_shader(ctx, node, socket):
    shaders = [s for s in getattr(node, "inputs", ()) if getattr(s, "type", "") == "SHADER"]
    children = [ctx.eval_input(node, s) for s in shaders[:2]]
    while len(children) < 2:
        children.append(None)
    return Closure("add", ctx.label(node), {}, children=children)


@maps("ShaderNodeEmission")
def emission(ctx, node, socket):
    return Closure("emission", ctx.label(node), {
        "color": ctx.input(node, "Color", default=(1.0, 1.0, 1.0)),
        "strength": ctx.input(node, "Strength", default=1.0),
    })


@maps("ShaderNodeBackground")
def background(ctx, node, socket):
    return Closure("background", ctx.label(node), {
        "color": ctx.input(node, "Color", default=(0.8, 0.8, 0.8)),
        "strength": ctx.input(node, "Strength", default=1.0),
    })


@maps("ShaderNodeHoldout")
def holdout(ctx, node, socket):
    return Closure("holdout", ctx.label(node), {})


def _volume(ctx, node, params, **props):
    return Closure("volume", ctx.label(node), params, props=props)


@maps("ShaderNodeVolumePrincipled")
def volume_principled(ctx, node, socket):
    # The attribute names select grids of a Volume object (lowering); Cycles multiplies
    # density, colour and temperature by them where the object has them.
    return _volume(ctx, node, {
        "color": ctx.input(node, "Color", default=(0.5, 0.5, 0.5)),
        "density": ctx.input(node, "Density", default=1.0),
        "anisotropy": ctx.input(node, "Anisotropy", default=0.0),
        "absorption_color": ctx.input(node, "Absorption Color", default=(0.0, 0.0, 0.0)),
        "emission_strength": ctx.input(node, "Emission Strength", default=0.0),
        "emission_color": ctx.input(node, "Emission Color", default=(1.0, 1.0, 1.0)),
        "blackbody_intensity": ctx.input(node, "Blackbody Intensity", default=0.0),
        "blackbody_tint": ctx.input(node, "Blackbody Tint", default=(1.0, 1.0, 1.0)),
        "temperature": ctx.input(node, "Temperature", default=1000.0),
    }, density_attribute=ctx.input_string(node, "Density Attribute"),
        color_attribute=ctx.input_string(node, "Color Attribute"),
        temperature_attribute=ctx.input_string(node, "Temperature Attribute"),
        # Cycles 3.4 (svm_node_principled_volume) absorbs by 1 - sqrt(Absorption Color).
        absorption_color_sqrt=True)


@maps("ShaderNodeVolumeScatter")
def volume_scatter(ctx, node, socket):
    return _volume(ctx, node, {
        "color": ctx.input(node, "Color", default=(0.8, 0.8, 0.8)),
        "density": ctx.input(node, "Density", default=1.0),
        "anisotropy": ctx.input(node, "Anisotropy", default=0.0),
        "absorption_color": Const((1.0, 1.0, 1.0)),  # scattering only
    })


@maps("ShaderNodeVolumeAbsorption")
def volume_absorption(ctx, node, socket):
    # Cycles: sigma_a = (1 - color) density.  Engine: (1 - absorption_color)(1 - color) density.
    return _volume(ctx, node, {
        "color": Const((0.0, 0.0, 0.0)),
        "density": ctx.input(node, "Density", default=1.0),
        "absorption_color": ctx.input(node, "Color", default=(0.8, 0.8, 0.8)),
    })
