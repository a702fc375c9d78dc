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
