"""Attribute nodes of type Object and Instancer: values of the object itself (a custom property
such as ob["tint"], or an RNA path such as "color" or "location"), which the engine reads per
instance (instance params "object_attributes" / "instancer_attributes", docs/scene-format.md).

Looked up as Cycles 3.4 does (lookup_instance_property, which follows Blender's
find_rna_property_rgba): Instancer first tries the instance's particle system (its settings,
then itself) and the object that instances it; then both try the object and its data. On each,
a custom property of that name first, then the name as an RNA path. A number n is
(n, n, n, 1), an array of up to 4 numbers fills (0, 0, 0, 1); anything else is not found, and
a name found nowhere reads 0 in the engine, as in Cycles.

Attribute nodes of type View Layer read one value for the whole render (view_layer_lookup):
the view layer's, else the scene's, else its world's, found the same way (Cycles 3.4, measured:
a view layer's custom property wins over the scene's, the scene's over the world's; an RNA path
such as "render.resolution_x" reads the scene's setting; a name found nowhere reads 0)."""

OBJECT_TYPES = ("OBJECT", "INSTANCER")


def tree_object_attributes(tree, depth=0):
    """The (attribute_type, name) pairs of a material node tree's Attribute nodes of type Object
    or Instancer (groups followed a few levels)."""
    found = set()
    if tree is None or depth > 4:
        return found
    for node in tree.nodes:
        if node.bl_idname == "ShaderNodeAttribute":
            kind = getattr(node, "attribute_type", "GEOMETRY")
            if kind in OBJECT_TYPES and node.attribute_name:
                found.add((kind, node.attribute_name))
        elif node.bl_idname == "ShaderNodeGroup" and node.node_tree is not None:
            found |= tree_object_attributes(node.node_tree, depth + 1)
    return found


def _rgba(value):
    if isinstance(value, str):
        return None
    if isinstance(value, (bool, int, float)):
        v = float(value)
        return [v, v, v, 1.0]
    try:
        items = [float(x) for x in value]
    except (TypeError, ValueError):
        return None
    if not 1 <= len(items) <= 4:
        return None
    out = [0.0, 0.0, 0.0, 1.0]
    out[:len(items)] = items
    return out


def _lookup(block, name):
    """The RGBA value of `name` on an ID or struct (None: not found)."""
    if block is None:
        return None
    value = None
    try:
        value = block.get(name)  # a custom property
    except (AttributeError, TypeError, KeyError):
        pass
    if value is None:
        try:
            value = block.path_resolve(name)
        except (ValueError, TypeError, AttributeError):
            return None
    return _rgba(value)


def attribute_value(ob, inst, kind, name):
    """What an Attribute node of type `kind` named `name` reads on object ob (inst: the depsgraph
    instance, or None)."""
    if kind == "INSTANCER" and inst is not None and getattr(inst, "is_instance", False):
        psys = getattr(inst, "particle_system", None)
        candidates = [getattr(psys, "settings", None), psys] if psys is not None else []
        candidates.append(getattr(inst, "parent", None))
        for block in candidates:
            value = _lookup(block, name)
            if value is not None:
                return value
    for block in (ob, getattr(ob, "data", None)):
        value = _lookup(block, name)
        if value is not None:
            return value
    return None


def instance_attributes(ob, inst, wanted):
    """The instance params for the (attribute_type, name) pairs `wanted`: {"object_attributes":
    {name: [r, g, b, a]}, "instancer_attributes": {...}}, the names found only."""
    out = {}
    for kind, name in sorted(wanted):
        value = attribute_value(ob, inst, kind, name)
        if value is not None:
            out.setdefault("instancer_attributes" if kind == "INSTANCER" else "object_attributes", {})[name] = value
    return out


def view_layer_lookup(view_layer, scene):
    """The lookup shaders_map's conversions take for Attribute nodes of type View Layer:
    name -> RGBA or None."""
    def lookup(name):
        if not name:
            return None
        for block in (view_layer, scene, getattr(scene, "world", None)):
            value = _lookup(block, name)
            if value is not None:
                return value
        return None
    return lookup
