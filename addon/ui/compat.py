"""Let Cycles' material, light, world, object and pass panels show for our engine, and
offer the shader nodes in the node editor's Add menu (3.x hides them for other engines)."""

import sys

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


def _cycles_base():
    """Cycles' panel base class (cycles.ui.CyclesButtonsPanel), or None without Cycles."""
    ui = sys.modules.get("cycles.ui")
    return getattr(ui, "CyclesButtonsPanel", None)


def _hidden_for_us(poll):
    """A poll that keeps a Cycles-only panel hidden under our engine, whatever it checks."""
    @classmethod
    def hidden(cls, context):
        return context.engine != ENGINE_ID and poll(context)
    return hidden


def register():
    base = _cycles_base()
    for panel in _all_panels():
        engines = getattr(panel, "COMPAT_ENGINES", None)
        if not isinstance(engines, set) or "CYCLES" not in engines or ENGINE_ID in engines:
            continue
        # Cycles' panels share one COMPAT_ENGINES set through their base class: give each
        # patched panel its own copy, and remember what it had, so unregister restores it.
        _patched.append((panel, "COMPAT_ENGINES", panel.__dict__.get("COMPAT_ENGINES")))
        if not _wanted(panel.__name__):
            # Cycles' own render settings stay Cycles': their set without us, and a poll that
            # says so (some call the base's poll by name, which lets us in below).
            panel.COMPAT_ENGINES = set(engines)
            if base is not None and issubclass(panel, base):
                _patched.append((panel, "poll", panel.__dict__.get("poll")))
                panel.poll = _hidden_for_us(panel.poll)
            continue
        panel.COMPAT_ENGINES = set(engines) | {ENGINE_ID}
    if base is not None and ENGINE_ID not in base.COMPAT_ENGINES:
        # Most of Cycles' panels poll through CyclesButtonsPanel.poll(context) called by name,
        # which reads the base's own set: without us in it their material, light, world,
        # object visibility and motion blur panels stayed hidden under our engine.
        _patched.append((base, "COMPAT_ENGINES", base.__dict__.get("COMPAT_ENGINES")))
        base.COMPAT_ENGINES = set(base.COMPAT_ENGINES) | {ENGINE_ID}
    _register_node_categories()


def unregister():
    _unregister_node_categories()
    while _patched:
        panel, name, original = _patched.pop()
        if original is None:
            try:
                delattr(panel, name)
            except AttributeError:
                pass
        else:
            setattr(panel, name, original)


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
