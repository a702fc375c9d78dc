"""Walking a Cycles node tree: links, reroutes, node groups, muted nodes, sockets.

Works on bpy node trees and on stand-in objects with the same attributes:
tree.nodes, tree.links (from_node, from_socket, to_node, to_socket, is_muted, is_valid),
node.bl_idname, node.name, node.inputs/outputs (identifier, name, type, default_value),
node.mute, node.internal_links, node.node_tree (groups), node.is_active_output, node.target.

Nothing here imports bpy.  The walk never hangs: cycles are cut with a warning naming the
node, over-deep graphs raise LimitError naming it (limits.py).
"""

import math

from .ir import Const, Expr, Closure
from .issues import Issues
from .limits import MAX_DEPTH, LimitError
from .registry import HANDLERS

LUMINANCE = (0.2126, 0.7152, 0.0722)  # Blender's default scene-linear Rec.709 luminance

GROUP_INPUT = "NodeGroupInput"
GROUP_OUTPUT = "NodeGroupOutput"
REROUTE = "NodeReroute"
GROUP_NODES = ("ShaderNodeGroup", "NodeCustomGroup")


def ptr(x):
    """Stable identity of a bpy struct (as_pointer) or of a stand-in object (id)."""
    f = getattr(x, "as_pointer", None)
    if f is not None:
        try:
            return f()
        except Exception:  # pragma: no cover - defensive
            pass
    return id(x)


def socket_value(socket):
    """The constant held by an unlinked socket, as float or 3-tuple (None for shaders)."""
    stype = getattr(socket, "type", "VALUE")
    if stype == "SHADER":
        return None
    dv = getattr(socket, "default_value", None)
    if dv is None:
        return 0.0 if stype in ("VALUE", "INT", "BOOLEAN") else (0.0, 0.0, 0.0)
    if isinstance(dv, (int, float, bool)):
        v = float(dv)
        return (v, v, v) if stype in ("RGBA", "VECTOR") else v
    try:
        t = tuple(float(x) for x in dv)
    except TypeError:
        return 0.0
    if stype in ("VALUE", "INT", "BOOLEAN"):
        return t[0] if t else 0.0
    return (t + (0.0, 0.0, 0.0))[:3]


def _finite(v):
    """v with every non-finite number (inf, nan) replaced by 0, and whether it was finite."""
    if isinstance(v, float):
        return (v, True) if math.isfinite(v) else (0.0, False)
    out = tuple(x if math.isfinite(x) else 0.0 for x in v)
    return out, all(math.isfinite(x) for x in v)


def find_socket(sockets, *names):
    """A socket by identifier, then by name, trying each name in turn (4.x renames)."""
    items = list(sockets)
    for n in names:
        for s in items:
            if getattr(s, "identifier", None) == n:
                return s
        for s in items:
            if getattr(s, "name", None) == n and getattr(s, "enabled", True):
                return s
        for s in items:
            if getattr(s, "name", None) == n:
                return s
    return None


def node_label(node, frame=None):
    idname = getattr(node, "bl_idname", type(node).__name__)
    kind = _pretty(idname)
    name = getattr(node, "name", "?")
    path = frame.path() if frame is not None else ""
    return "%s '%s%s'" % (kind, path, name)


def _pretty(idname):
    for prefix in ("ShaderNodeBsdf", "ShaderNodeTex", "ShaderNode", "Node"):
        if idname.startswith(prefix) and len(idname) > len(prefix):
            base = idname[len(prefix):]
            if prefix == "ShaderNodeBsdf":
                return base + " BSDF"
            if prefix == "ShaderNodeTex":
                return base + " Texture"
            return base
    return idname


class _Frame:
    """One level of node-group nesting: the group node and the frame it sits in."""

    __slots__ = ("group_node", "parent", "tree", "depth", "key")

    def __init__(self, group_node, parent, tree):
        self.group_node = group_node
        self.parent = parent
        self.tree = tree
        self.depth = 0 if parent is None else parent.depth + 1
        self.key = (ptr(group_node) if group_node is not None else 0,
                    parent.key if parent is not None else None)

    def path(self):
        names = []
        f = self
        while f is not None and f.group_node is not None:
            names.append(getattr(f.group_node, "name", "?"))
            f = f.parent
        return "".join(n + "/" for n in reversed(names))


class _LinkIndex:
    def __init__(self):
        self._by_tree = {}

    def link_to(self, tree, socket):
        key = ptr(tree)
        table = self._by_tree.get(key)
        if table is None:
            table = {}
            for link in list(getattr(tree, "links", ()) or ()):
                if getattr(link, "is_muted", False) or not getattr(link, "is_valid", True):
                    continue
                to_sock = getattr(link, "to_socket", None)
                if to_sock is None or getattr(link, "from_socket", None) is None:
                    continue
                table.setdefault(ptr(to_sock), link)
            self._by_tree[key] = table
        return table.get(ptr(socket))


class Context:
    """Passed to node handlers.  Handlers call ``input``/``closure``/``warn``."""

    def __init__(self, tree, issues=None):
        self.issues = issues if issues is not None else Issues()
        self._links = _LinkIndex()
        self._memo = {}
        self._active = set()
        self._frame = _Frame(None, None, tree)
        self.root = tree

    # ---- helpers for handlers -------------------------------------------------
    def label(self, node):
        return node_label(node, self._frame)

    def warn(self, node, reason):
        self.issues.add(self.label(node), reason)

    def constant(self, node, socket):
        """The constant a socket holds (None for shaders). A value that is not finite (a script
        can set inf or nan; the engine refuses them) becomes 0, with a warning naming the node
        and the socket."""
        if getattr(socket, "type", "") == "SHADER":
            return None
        v, ok = _finite(socket_value(socket))
        if not ok:
            self.warn(node, "'%s' is not finite (%s), using 0" % (getattr(socket, "name", "?"),
                                                                    getattr(socket, "default_value", "?")))
        return Const(v)

    def socket(self, node, *names):
        return find_socket(getattr(node, "inputs", ()), *names)

    def has_input(self, node, *names):
        return self.socket(node, *names) is not None

    def is_linked(self, node, *names):
        s = self.socket(node, *names)
        return s is not None and self._links.link_to(self._frame.tree, s) is not None

    def input(self, node, *names, default=0.0):
        """The value flowing into an input (an IR value), converted to the socket's type."""
        s = self.socket(node, *names)
        if s is None:
            return Const(default)
        return self.eval_input(node, s)

    def input_const(self, node, *names, default=0.0):
        """Like input, but only when the socket holds a constant (None otherwise)."""
        ir = self.input(node, *names, default=default)
        return ir.value if isinstance(ir, Const) else None

    def input_string(self, node, *names, default=""):
        """The text of a string socket (Principled Volume's attribute names; never linked)."""
        s = self.socket(node, *names)
        v = getattr(s, "default_value", default) if s is not None else default
        return v if isinstance(v, str) else default

    def closure(self, node, *names):
        s = self.socket(node, *names)
        if s is None:
            return None
        return self.eval_input(node, s)

    def each_node(self, visit):
        """visit(node) for every node of the tree and of the node groups it uses (unmuted, each
        use of a group on its own), with this context inside that use of the group: input()
        of a node there reads what flows into it (Cycles flattens groups alike)."""
        def walk(tree):
            for node in list(getattr(tree, "nodes", ()) or ()):
                if getattr(node, "bl_idname", "") in GROUP_NODES:
                    inner = getattr(node, "node_tree", None)
                    if inner is None or getattr(node, "mute", False) or self._frame.depth >= 16:
                        continue
                    saved = self._frame
                    self._frame = _Frame(node, saved, inner)
                    try:
                        walk(inner)
                    finally:
                        self._frame = saved
                else:
                    visit(node)
        walk(self._frame.tree)

    # ---- the walk ------------------------------------------------------------
    def eval_input(self, node, socket, passthrough=False):
        want = getattr(socket, "type", "VALUE")
        link = self._links.link_to(self._frame.tree, socket)
        if link is None:
            return self.constant(node, socket)
        src = self.eval_output(link.from_node, link.from_socket)
        if passthrough:  # reroutes take the type of what is plugged into them
            return src
        return convert(src, getattr(link.from_socket, "type", want), want,
                       self.label(link.from_node))

    def eval_output(self, node, socket):
        key = (self._frame.key, ptr(node), getattr(socket, "identifier", None) or ptr(socket))
        if key in self._memo:
            return self._memo[key]
        if key in self._active:
            self.warn(node, "cycle in the node graph, link cut")
            return self.constant(node, socket)
        if len(self._active) >= MAX_DEPTH:
            raise LimitError("node graph too deep: more than %d nodes on one path, at %s"
                             % (MAX_DEPTH, self.label(node)))
        self._active.add(key)
        try:
            result = self._eval_output(node, socket)
        except RecursionError:  # Blender called from deep already: the same limit, met earlier
            raise LimitError("node graph too deep: Python's recursion limit reached at %s (%d nodes on the path)"
                             % (self.label(node), len(self._active))) from None
        finally:
            self._active.discard(key)
        self._memo[key] = result
        return result

    def _eval_output(self, node, socket):
        idname = getattr(node, "bl_idname", "")
        if idname == REROUTE:
            inp = list(getattr(node, "inputs", ()))
            if not inp:
                return self.constant(node, socket)
            return self.eval_input(node, inp[0], passthrough=True)
        if getattr(node, "mute", False):
            return self._eval_muted(node, socket)
        if idname in GROUP_NODES:
            return self._eval_group(node, socket)
        if idname == GROUP_INPUT:
            return self._eval_group_input(node, socket)
        handler = HANDLERS.get(idname)
        if handler is None:
            return self._unsupported(node, socket)
        return handler(self, node, socket)

    def _eval_muted(self, node, socket):
        ident = getattr(socket, "identifier", None)
        for il in list(getattr(node, "internal_links", ()) or ()):
            to = getattr(il, "to_socket", None)
            if to is None:
                continue
            if ptr(to) == ptr(socket) or (ident is not None and getattr(to, "identifier", None) == ident):
                return self.eval_input(node, il.from_socket)
        # Blender passes nothing through: the output's default (no shader for closures).
        return self.constant(node, socket)

    def _eval_group(self, node, socket):
        tree = getattr(node, "node_tree", None)
        if tree is None:
            self.warn(node, "node group has no tree")
            return self.constant(node, socket)
        if self._frame.depth >= 16:
            self.warn(node, "node groups nested too deep (recursive group?)")
            return self.constant(node, socket)
        out_node = _group_output(tree)
        if out_node is None:
            return self.constant(node, socket)
        inner = find_socket(getattr(out_node, "inputs", ()),
                            getattr(socket, "identifier", ""), getattr(socket, "name", ""))
        if inner is None:
            return self.constant(node, socket)
        saved = self._frame
        self._frame = _Frame(node, saved, tree)
        try:
            return self.eval_input(out_node, inner)
        finally:
            self._frame = saved

    def _eval_group_input(self, node, socket):
        frame = self._frame
        if frame.group_node is None:
            return self.constant(node, socket)
        outer = find_socket(getattr(frame.group_node, "inputs", ()),
                            getattr(socket, "identifier", ""), getattr(socket, "name", ""))
        if outer is None:
            return self.constant(node, socket)
        self._frame = frame.parent
        try:
            return self.eval_input(frame.group_node, outer)
        finally:
            self._frame = frame

    def _unsupported(self, node, socket):
        idname = getattr(node, "bl_idname", "?")
        label = self.label(node)
        if getattr(socket, "type", "") == "SHADER":
            self.warn(node, "unsupported shader node %s, using a diffuse fallback" % idname)
            color_sock = self.socket(node, "Color", "Base Color")
            color = self.eval_input(node, color_sock) if color_sock is not None else Const((0.8, 0.8, 0.8))
            return Closure("diffuse", label, {"color": color}, props={"fallback": idname})
        self.warn(node, "unsupported node %s, using a constant" % idname)
        if getattr(socket, "type", "") == "VECTOR":
            return Const((0.0, 0.0, 0.0))
        if getattr(socket, "type", "") == "RGBA":
            return Const((0.5, 0.5, 0.5))
        return Const(0.5)


def _group_output(tree):
    outs = [n for n in list(getattr(tree, "nodes", ())) if getattr(n, "bl_idname", "") == GROUP_OUTPUT]
    for n in outs:
        if getattr(n, "is_active_output", False):
            return n
    return outs[0] if outs else None


def convert(ir, from_type, to_type, label):
    """Blender's implicit socket conversions (colour->float is luminance)."""
    if ir is None:
        if to_type == "SHADER":
            return None
        return Const(0.0 if to_type in ("VALUE", "INT", "BOOLEAN") else (0.0, 0.0, 0.0))
    if to_type == "SHADER":
        if isinstance(ir, Closure):
            return ir
        # A colour or value plugged into a shader socket is an emission (as in Cycles).
        return Closure("emission", label, {"color": _as_color(ir, label), "strength": Const(1.0)},
                       props={"implicit": True})
    if isinstance(ir, Closure):
        # A shader plugged into a value socket: Blender gives 0.
        return Const(0.0 if to_type in ("VALUE", "INT", "BOOLEAN") else (0.0, 0.0, 0.0))
    if to_type in ("VALUE", "INT", "BOOLEAN"):
        if isinstance(ir, Const):
            if isinstance(ir.value, float):
                return ir
            return Const(to_float(ir.value, from_type))
        if from_type in ("RGBA", "VECTOR"):
            return Expr("to_float", label, {"value": ir}, {"from": from_type})
        return ir
    # RGBA / VECTOR
    return _as_color(ir, label)


def _as_color(ir, label):
    if isinstance(ir, Const):
        v = ir.value
        return ir if not isinstance(v, float) else Const((v, v, v))
    return Expr("to_vec3", label, {"value": ir})


def to_float(v, from_type="RGBA"):
    if isinstance(v, float):
        return v
    if from_type == "VECTOR":
        return (v[0] + v[1] + v[2]) / 3.0
    return LUMINANCE[0] * v[0] + LUMINANCE[1] * v[1] + LUMINANCE[2] * v[2]


def find_output_node(tree, idnames=("ShaderNodeOutputMaterial",)):
    """The output node Cycles would use: active output targeting Cycles or All."""
    nodes = [n for n in list(getattr(tree, "nodes", ()) or ()) if getattr(n, "bl_idname", "") in idnames]
    if not nodes:
        return None

    def rank(n):
        target = getattr(n, "target", "ALL")
        ok = target in ("ALL", "CYCLES")
        return (not ok, not getattr(n, "is_active_output", False), target != "CYCLES")

    nodes.sort(key=rank)
    best = nodes[0]
    if getattr(best, "target", "ALL") not in ("ALL", "CYCLES"):
        return None
    return best
