"""Limits on node trees, so that no node tree can crash or hang Blender (docs/scene-format.md, Limits).

A node tree beyond a limit raises LimitError naming the node; convert_material / convert_world
turn it into the magenta error material (default world) and one message naming the material.
"""

# Nodes on one evaluation path, groups included. The walk recurses about five Python frames
# per node: 120 stays well inside Python's default recursion limit (1000) wherever Blender
# calls from; the engine's own limit (256 texture nodes / Mix shaders) is above it.
MAX_DEPTH = 120

# Nodes of the engine description once written out: the description is a tree, so a node
# used twice is written twice, and a chain of N nodes each feeding the next twice writes
# 2^N (30 such Math nodes: 1e9). The engine takes 100,000 nodes in well under a second.
MAX_WRITTEN_NODES = 100000


class LimitError(ValueError):
    """A node tree beyond one of the limits above; the message names the node."""


def written_size(params, limit=MAX_WRITTEN_NODES):
    """Dicts and lists in `params` written out as a tree (a shared object counts once per use),
    counted without recursion in time linear in the distinct objects; stops past `limit`."""
    sizes = {}  # id -> written size of a finished object
    stack = [(params, False)]
    while stack:
        obj, children_done = stack.pop()
        key = id(obj)
        if key in sizes:
            continue
        children = obj.values() if isinstance(obj, dict) else obj
        children = [c for c in children if isinstance(c, (dict, list))]
        if not children_done:
            stack.append((obj, True))
            stack.extend((c, False) for c in children if id(c) not in sizes)
            continue
        size = 1 + sum(sizes[id(c)] for c in children)
        if size > limit:
            return size
        sizes[key] = size
    return sizes.get(id(params), 0) if isinstance(params, (dict, list)) else 0
