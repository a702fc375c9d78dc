"""Let Cycles' material, light, world, object and pass panels show for our engine, and
offer the shader nodes in the node editor's Add menu (3.x hides them for other engines)."""

import bpy

ENGINE_ID = "RENDEZVOUS"
SKIP = {"VIEWLAYER_PT_filter", "VIEWLAYER_PT_layer_passes"}

_patched = []
_node_categories_registered = False


def _wanted(name):
    if name in SKIP:
        return False
    if name.startswith("CYCLES_RENDER_PT_"):
        # Cycles' own render settings stay Cycles'; its pass panels are useful to us.
        return "_passes" in name
    return True


def _all_panels():
    seen, stack = set(), list(bpy.types.Panel.__subclasses__())
    while stack:
        cls = stack.pop()
        if cls in seen:
            continue
        seen.add(cls)
        stack.extend(cls.__subclasses__())
        yield cls


def register():
    for panel in _all_panels():
        engines = getattr(panel, "COMPAT_ENGINES", None)
        if not isinstance(engines, set) or "CYCLES" not in engines or ENGINE_ID in engines:
            continue
        if not _wanted(panel.__name__):
            continue
        # Cycles' panels share one COMPAT_ENGINES set through their base class: give each
        # patched panel its own copy, and remember what it had, so unregister restores it.
        _patched.append((panel, panel.__dict__.get("COMPAT_ENGINES")))
        panel.COMPAT_ENGINES = set(engines) | {ENGINE_ID}
    _register_node_categories()


def unregister():
    _unregister_node_categories()
    while _patched:
        panel, original = _patched.pop()
        if original is None:
            try:
                del panel.COMPAT_ENGINES
            except AttributeError:
                pass
        else:
            panel.COMPAT_ENGINES = original


# ---- node editor Add menu -------------------------------------------------------------
NODE_CATEGORIES = {
    "RDV_INPUT": ("Input", ["ShaderNodeTexCoord", "ShaderNodeUVMap", "ShaderNodeRGB", "ShaderNodeValue",
                            "ShaderNodeVertexColor", "ShaderNodeAttribute"]),
    "RDV_SHADER": ("Shader", ["ShaderNodeBsdfPrincipled", "ShaderNodeBsdfDiffuse", "ShaderNodeBsdfGlossy",
                              "ShaderNodeBsdfAnisotropic", "ShaderNodeBsdfGlass", "ShaderNodeBsdfRefraction",
                              "ShaderNodeBsdfTransparent", "ShaderNodeBsdfTranslucent", "ShaderNodeEmission",
                              "ShaderNodeBackground", "ShaderNodeMixShader", "ShaderNodeAddShader",
                              "ShaderNodeHoldout"]),
    "RDV_TEXTURE": ("Texture", ["ShaderNodeTexImage", "ShaderNodeTexEnvironment", "ShaderNodeTexChecker",
                                "ShaderNodeTexNoise", "ShaderNodeTexGradient"]),
    "RDV_COLOR": ("Color", ["ShaderNodeMix", "ShaderNodeMixRGB", "ShaderNodeInvert", "ShaderNodeGamma",
                            "ShaderNodeBrightContrast", "ShaderNodeHueSaturation"]),
    "RDV_VECTOR": ("Vector", ["ShaderNodeMapping", "ShaderNodeNormalMap", "ShaderNodeBump"]),
    "RDV_CONVERTER": ("Converter", ["ShaderNodeMath", "ShaderNodeVectorMath", "ShaderNodeValToRGB",
                                    "ShaderNodeClamp", "ShaderNodeMapRange", "ShaderNodeSeparateColor",
                                    "ShaderNodeCombineColor", "ShaderNodeRGBToBW"]),
    "RDV_OUTPUT": ("Output", ["ShaderNodeOutputMaterial", "ShaderNodeOutputWorld"]),
}


def _register_node_categories():
    global _node_categories_registered
    try:
        import nodeitems_utils
        from nodeitems_utils import NodeCategory, NodeItem
    except ImportError:  # removed in newer Blender: its Add menus list nodes for every engine
        return

    class RendezvousNodeCategory(NodeCategory):
        @classmethod
        def poll(cls, context):
            return context.engine == ENGINE_ID and context.space_data.tree_type == "ShaderNodeTree"

    cats = []
    for ident, (label, idnames) in NODE_CATEGORIES.items():
        items = [NodeItem(i) for i in idnames if hasattr(bpy.types, i)]
        cats.append(RendezvousNodeCategory(ident, label, items=items))
    try:
        nodeitems_utils.register_node_categories("RENDEZVOUS_NODES", cats)
        _node_categories_registered = True
    except Exception:
        _node_categories_registered = False


def _unregister_node_categories():
    global _node_categories_registered
    if not _node_categories_registered:
        return
    import nodeitems_utils
    try:
        nodeitems_utils.unregister_node_categories("RENDEZVOUS_NODES")
    finally:
        _node_categories_registered = False
