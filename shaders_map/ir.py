"""Engine-neutral intermediate representation of a Cycles shader graph.

Three kinds of IR objects:

* ``Const(value)``: a float or an RGB/XYZ 3-tuple (a socket left at its constant);
* ``Expr(op, node, args, props)``: a value computed by a node (texture, math, ...);
* ``Closure(kind, node, params, children)``: a shader (BSDF, emission, mix, add, ...).

The IR keeps the full Cycles semantics; ``lowering`` maps it onto what the engine's
material types accept today.  ``to_dict()`` gives a JSON-friendly view for debugging.
"""


class Const:
    __slots__ = ("value",)

    def __init__(self, value):
        if isinstance(value, (int, float)):
            self.value = float(value)
        else:
            v = tuple(float(x) for x in value)
            self.value = v[:3] if len(v) >= 3 else (v + (0.0, 0.0, 0.0))[:3]

    def to_dict(self):
        return self.value if isinstance(self.value, float) else list(self.value)

    def __repr__(self):
        return "Const(%r)" % (self.value,)


class Expr:
    """A value computed by a node.  ``node`` is the label of the node that made it."""

    __slots__ = ("op", "node", "args", "props")

    def __init__(self, op, node, args=None, props=None):
        self.op = op
        self.node = node
        self.args = dict(args or {})
        self.props = dict(props or {})

    def to_dict(self):
        d = {"op": self.op, "node": self.node}
        if self.args:
            d["args"] = {k: to_dict(v) for k, v in self.args.items()}
        if self.props:
            d["props"] = {k: _plain(v) for k, v in self.props.items()}
        return d

    def __repr__(self):
        return "Expr(%s, %r)" % (self.op, self.node)


class Closure:
    """A shader.  kind: diffuse, glossy, anisotropic, glass, refraction, transparent,
    translucent, emission, background, principled, holdout, mix, add, unsupported."""

    __slots__ = ("kind", "node", "params", "children", "props")

    def __init__(self, kind, node, params=None, children=(), props=None):
        self.kind = kind
        self.node = node
        self.params = dict(params or {})
        self.children = list(children)
        self.props = dict(props or {})

    def to_dict(self):
        d = {"closure": self.kind, "node": self.node}
        if self.params:
            d["params"] = {k: to_dict(v) for k, v in self.params.items()}
        if self.children:
            d["children"] = [to_dict(c) for c in self.children]
        if self.props:
            d["props"] = {k: _plain(v) for k, v in self.props.items()}
        return d

    def __repr__(self):
        return "Closure(%s, %r)" % (self.kind, self.node)


def to_dict(ir):
    if ir is None:
        return None
    return ir.to_dict()


def _plain(v):
    if isinstance(v, (str, int, float, bool)) or v is None:
        return v
    if isinstance(v, (list, tuple)):
        return [_plain(x) for x in v]
    if isinstance(v, dict):
        return {str(k): _plain(x) for k, x in v.items()}
    return str(v)


def is_const(ir):
    return isinstance(ir, Const)
