"""Registries of node handlers (graph -> IR) and evaluators (IR -> constants).

A node family module declares::

    @maps("ShaderNodeBsdfDiffuse")
    def diffuse(ctx, node, socket):
        return Closure("diffuse", ctx.label(node), {"color": ctx.input(node, "Color")})

    @evaluates("math")
    def eval_math(ev, expr):
        ...
"""

HANDLERS = {}
EVALUATORS = {}


def maps(*bl_idnames):
    def deco(fn):
        for name in bl_idnames:
            HANDLERS[name] = fn
        return fn
    return deco


def evaluates(*ops):
    def deco(fn):
        for op in ops:
            EVALUATORS[op] = fn
        return fn
    return deco


def supported_nodes():
    return sorted(HANDLERS)
