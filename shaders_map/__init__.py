"""shaders_map: Cycles node trees -> Rendezvous material descriptions.

Pure Python, no bpy import: it works on bpy data and on stand-in objects alike.

    desc = translate_material(material.node_tree, name=material.name)   # neutral IR
    params, warning = convert_material(material, image_average=fn, image_file=fn2)  # engine params

``image_file(image)`` gives the path of a file the engine can read for a bpy image (or None:
the image is then replaced by its average colour, with a warning).

``convert_*`` return the engine's JSON parameters and ONE warning string (or None)
naming every node that was approximated or is unsupported.
"""

from . import nodes  # noqa: F401  (fills the registries)
from .graph import Context, find_output_node, find_socket, node_label
from .ir import Const, Expr, Closure, to_dict
from .issues import Issues
from .limits import LimitError, written_size, MAX_WRITTEN_NODES
from .lowering import lower_surface, lower_world, lower_light, DEFAULT_SURFACE, ENGINE_TYPES, DEFAULT_COLOR_ATTRIBUTE
from .registry import maps, evaluates, supported_nodes, HANDLERS
from . import ray_kinds
from .nodes.inputs import MESH_DERIVED_ATTRIBUTES

__all__ = [
    "translate_material", "translate_world", "convert_material", "convert_light", "convert_material_variants", "convert_world",
    "MaterialDescription", "WorldDescription", "maps", "evaluates", "supported_nodes",
    "Const", "Expr", "Closure", "Issues", "DEFAULT_SURFACE", "ENGINE_TYPES", "DEFAULT_COLOR_ATTRIBUTE",
    "LimitError", "ERROR_SURFACE", "MESH_DERIVED_ATTRIBUTES",
]

# What a material beyond a limit renders as: Blender's magenta for a material it cannot use.
ERROR_SURFACE = {"type": "diffuse", "color": [1.0, 0.0, 1.0]}
DEFAULT_WORLD = {"color": [0.0, 0.0, 0.0], "strength": 1.0}


class MaterialDescription:
    """The engine-neutral description of one material's active Cycles output."""

    def __init__(self, name):
        self.name = name
        self.surface = None
        self.volume = None
        self.displacement = None  # IR of the Material Output's Displacement, when linked
        self.displacement_method = "BUMP"  # Material > Settings > Displacement (Cycles')
        # The tree's AOV Output nodes: [(AOV name, IR of Color, IR of Value)] (shader AOVs)
        self.aovs = []
        self.output_label = "Material Output"
        self.issues = Issues()

    def to_dict(self):
        return {"name": self.name, "surface": to_dict(self.surface), "volume": to_dict(self.volume),
                "displacement": to_dict(self.displacement),
                "issues": {k: v for k, v in self.issues.items()}}


class WorldDescription(MaterialDescription):
    pass


def _translate(tree, desc, output_ids):
    if tree is None:
        return desc
    try:
        out = find_output_node(tree, output_ids)
    except Exception as exc:  # malformed tree
        desc.issues.add("node tree", "could not be read (%s)" % exc)
        return desc
    if out is None:
        return desc
    ctx = Context(tree, desc.issues)
    desc.output_label = ctx.label(out)
    try:
        desc.surface = ctx.closure(out, "Surface")
        desc.volume = ctx.closure(out, "Volume")
        if ctx.socket(out, "Displacement") is not None and ctx.is_linked(out, "Displacement"):
            desc.displacement = ctx.input(out, "Displacement", default=(0.0, 0.0, 0.0))
        if isinstance(desc, MaterialDescription):
            # AOV Output nodes (Blender 3.4 keeps the AOV's name in the node's `name`), each
            # written to the view layer's shader AOV of its name (film/shader_aovs.h); those
            # inside node groups too, as Cycles flattens the groups.
            def aov_output(node):
                if getattr(node, "bl_idname", "") == "ShaderNodeOutputAOV" and not getattr(node, "mute", False) \
                        and getattr(node, "name", ""):
                    desc.aovs.append((node.name, ctx.input(node, "Color", default=(0.0, 0.0, 0.0)),
                                      ctx.input(node, "Value", default=0.0)))
            ctx.each_node(aov_output)
    except LimitError:
        raise  # the caller names the material
    except Exception as exc:  # never let a strange tree stop the render
        desc.issues.add(desc.output_label, "translation failed (%s: %s)" % (type(exc).__name__, exc))
    return desc


def translate_material(node_tree, name=""):
    return _translate(node_tree, MaterialDescription(name), ("ShaderNodeOutputMaterial",))


def translate_world(node_tree, name=""):
    return _translate(node_tree, WorldDescription(name), ("ShaderNodeOutputWorld",))


def _rgb(v, default):
    try:
        t = tuple(float(x) for x in v)
        return list(t[:3])
    except Exception:
        return list(default)


def convert_material(material, image_average=None, image_file=None, volume_grids=False, blender_version=None,
                     view_layer_attribute=None):
    """A bpy Material (or stand-in) -> (engine params, warning or None).  volume_grids: for a
    Volume object (grid references {"name": ...} in the medium, completed by the exporter).
    Material > Settings > Pass Index goes along as "pass_index" (the Material Index pass).
    blender_version (bpy.app.version): the Cycles the material is rendered as; before 3.5
    its microfacet closures are Cycles 3.4's ("microfacets": "cycles_3.4": separable GGX
    shadowing, glass split by the shading normal's Fresnel), from 3.5 on the engine's default.
    A material that looks different to different kinds of ray (Light Path's ray types) is
    here the one diffuse rays see, with a warning: convert_material_variants gives them all."""
    variants, warning = convert_material_variants(material, image_average, image_file, volume_grids, blender_version,
                                                  view_layer_attribute)
    if len(variants) == 1:
        return variants[0][1], warning
    note = "Material '%s': its look for each kind of ray (Light Path) needs one object copy per look; here " \
           "the one diffuse rays see" % getattr(material, "name", "?")
    params = ray_kinds.lighting_look(variants)
    return params, "%s; %s" % (warning, note) if warning else note


def convert_material_variants(material, image_average=None, image_file=None, volume_grids=False,
                              blender_version=None, view_layer_attribute=None):
    """A bpy Material -> ([(kinds, params)], warning or None): the material as convert_material
    gives it, once per group of the engine's ray kinds (ray_kinds.KINDS) that see it alike. One
    entry (kinds None) unless its surface reads Light Path's ray types (ray_kinds.py); the
    exporter then sends the object once per entry, visible to those kinds alone.
    view_layer_attribute(name): what an Attribute node of type View Layer reads, as RGBA (the
    view layer's, else the scene's, else the world's property of that name), or None (not
    found: 0, as Cycles); without it such a node is approximated, with a warning."""
    variants, warning = _convert_material(material, image_average, image_file, volume_grids, view_layer_attribute)
    index = int(getattr(material, "pass_index", 0) or 0) if material is not None else 0
    out = []
    for kinds, params in variants:
        if index:
            params = dict(params, pass_index=index)
        if blender_version is not None and tuple(blender_version) < (3, 5, 0) and params.get("type") != "volume":
            params = dict(params, microfacets="cycles_3.4")
        out.append((kinds, params))
    return out, warning


def _convert_material(material, image_average, image_file, volume_grids, view_layer_attribute=None):
    name = getattr(material, "name", "?")
    if material is None:
        return [(None, dict(DEFAULT_SURFACE))], None
    tree = getattr(material, "node_tree", None)
    if not getattr(material, "use_nodes", False) or tree is None:
        # Cycles: a material without nodes is a diffuse BSDF of its viewport colour.
        return [(None, {"type": "diffuse", "color": _rgb(getattr(material, "diffuse_color", None),
                                                         (0.8, 0.8, 0.8))})], None
    try:
        desc = _with_view_layer_attributes(translate_material(tree, name), view_layer_attribute)
        desc.displacement_method = displacement_method(material)
        variants = _lower_by_ray_kind(desc, image_average, image_file, volume_grids)
        for _, params in variants:
            _check_written_size(params)
    except LimitError as exc:
        return [(None, dict(ERROR_SURFACE))], "Material '%s': %s; rendered magenta" % (name, exc)
    return variants, desc.issues.format("Material", name)


def _aovs_with(aovs, replace):
    """AOV Outputs [(name, colour IR, value IR)] with replace(ir) applied to both inputs."""
    return [(name, replace(color), replace(value)) for name, color, value in aovs]


def _with_view_layer_attributes(desc, lookup):
    """desc with its Attribute nodes of type View Layer made the constants they are for the whole
    render (Cycles 3.4 reads them once: Color and Vector the value, Fac its RGB average, Alpha its
    alpha; all 0 for a name found nowhere)."""
    roots = [desc.surface, desc.volume, desc.displacement] + [x for _, color, value in desc.aovs for x in (color, value)]
    if lookup is None or not any(isinstance(x, Expr) and x.op == "attribute" and
                                 x.props.get("attribute_type") == "VIEW_LAYER" for x in ray_kinds.walk(roots)):
        return desc  # nothing to resolve: the description as it is

    def leaf(e):
        if e.op != "attribute" or e.props.get("attribute_type") != "VIEW_LAYER":
            return None
        rgba = lookup(e.props.get("attribute_name", "")) or (0.0, 0.0, 0.0, 0.0)
        output = e.props.get("output", "Color")
        if output == "Fac":
            return Const(sum(rgba[:3]) / 3.0)
        return Const(float(rgba[3])) if output == "Alpha" else Const(tuple(float(x) for x in rgba[:3]))
    memo = {}
    desc.surface = ray_kinds.replace_leaves(desc.surface, leaf, memo)
    desc.volume = ray_kinds.replace_leaves(desc.volume, leaf, memo)
    desc.displacement = ray_kinds.replace_leaves(desc.displacement, leaf, memo)
    desc.aovs = _aovs_with(desc.aovs, lambda ir: ray_kinds.replace_leaves(ir, leaf, memo))
    return desc


def displacement_method(material):
    """Material > Settings > Displacement: BUMP (Cycles' default), DISPLACEMENT or BOTH. Blender
    3.x keeps it in the Cycles add-on's settings (material.cycles), 4.1 on in the material."""
    for owner in (getattr(material, "cycles", None), material):
        method = getattr(owner, "displacement_method", None)
        if method in ("BUMP", "DISPLACEMENT", "BOTH"):
            return method
    return "BUMP"


def _camera_aovs(desc):
    """The AOV Outputs of a description as camera rays read them (Cycles writes them for camera
    rays and those that went on straight through transparent surfaces: Light Path's Is Camera
    Ray is 1 there), when the shader itself reads no ray type."""
    flags = ray_kinds.flag_outputs(*(x for _, color, value in desc.aovs for x in (color, value)))
    if flags:
        memo = {}
        desc.aovs = _aovs_with(desc.aovs, lambda ir: ray_kinds.substitute(ir, {"camera"}, memo))


def _lower_by_ray_kind(desc, image_average, image_file, volume_grids):
    """[(kinds or None, params)] of a translated material (ray_kinds.py)."""
    if not ray_kinds.flag_outputs(desc.surface, desc.volume):
        _camera_aovs(desc)
        params, _ = lower_surface(desc, image_average, image_file, volume_grids)
        return [(None, params)]

    def lower(flags):
        variant = MaterialDescription(desc.name)
        variant.issues, variant.output_label = desc.issues, desc.output_label
        variant.displacement_method = desc.displacement_method
        memo = {}
        variant.displacement = ray_kinds.substitute(desc.displacement, flags, memo)
        variant.aovs = _aovs_with(desc.aovs, lambda ir: ray_kinds.substitute(ir, flags, memo))
        variant.surface = ray_kinds.substitute(desc.surface, flags, memo)
        variant.volume = ray_kinds.substitute(desc.volume, flags, memo)
        return lower_surface(variant, image_average, image_file, volume_grids)[0]

    if desc.volume is not None or volume_grids:
        # Copies of a medium's boundary would each be crossed: one material, as diffuse rays see it.
        desc.issues.add(desc.output_label, "Light Path's ray types in a material with a volume: shaded as diffuse "
                                           "rays see it, for every ray")
        return [(None, lower(ray_kinds.KIND_FLAGS["diffuse"][0]))]
    variants = ray_kinds.kind_variants(lower, desc.issues, desc.output_label)
    return [(None, variants[0][1])] if len(variants) == 1 else variants


def _check_written_size(params):
    n = written_size(params)
    if n > MAX_WRITTEN_NODES:
        raise LimitError("node graph too large: more than %d nodes once shared nodes are written out per use "
                         "(nodes that feed one another more than once double it at every level)"
                         % MAX_WRITTEN_NODES)


def convert_world(world, image_average=None, image_file=None, view_layer_attribute=None):
    """A bpy World (or stand-in, or None) -> ({"color", "strength", ...}, warning or None).
    World > Mist Pass goes along as "mist" {"start", "depth", "falloff"} (the Mist pass).
    view_layer_attribute: as for convert_material_variants."""
    params, warning = _convert_world(world, image_average, image_file, view_layer_attribute)
    mist = getattr(world, "mist_settings", None)
    if mist is not None:
        params = dict(params, mist={"start": float(mist.start), "depth": float(mist.depth),
                                    "falloff": str(mist.falloff).lower()})
    return params, warning


def convert_light(light, view_layer_attribute=None, image_average=None, image_file=None):
    """A bpy Light's node tree (when it uses nodes) -> ({"color", "strength"} of its Emission, the
    engine's light "emission", or None) and one warning or None (docs/scene-format.md).
    image_average / image_file: as for convert_material_variants (an image over the lamp)."""
    tree = getattr(light, "node_tree", None)
    if light is None or not getattr(light, "use_nodes", False) or tree is None:
        return None, None
    name = getattr(light, "name", "?")
    desc = _with_view_layer_attributes(_translate(tree, MaterialDescription(name), ("ShaderNodeOutputLight",)),
                                       view_layer_attribute)
    emission, issues = lower_light(desc, image_average, image_file, sun=getattr(light, "type", "") == "SUN")
    return emission, issues.format("Light", name)


def _convert_world(world, image_average, image_file, view_layer_attribute=None):
    if world is None:
        return {"color": [0.0, 0.0, 0.0], "strength": 1.0}, None
    name = getattr(world, "name", "?")
    tree = getattr(world, "node_tree", None)
    if not getattr(world, "use_nodes", False) or tree is None:
        return {"color": _rgb(getattr(world, "color", None), (0.05, 0.05, 0.05)), "strength": 1.0}, None
    try:
        desc = _with_view_layer_attributes(translate_world(tree, name), view_layer_attribute)
        params, issues = _lower_world_by_ray_kind(desc, image_average, image_file)
        _check_written_size(params)
    except LimitError as exc:
        return dict(DEFAULT_WORLD), "World '%s': %s; rendered black" % (name, exc)
    return params, issues.format("World", name)


def _lower_world_by_ray_kind(desc, image_average, image_file):
    """lower_world, with a look of its own for camera rays ("camera") when the World's nodes
    read Light Path > Is Camera Ray (ray_kinds.py)."""
    used = ray_kinds.flag_outputs(desc.surface, desc.volume)
    if not used:
        _camera_aovs(desc)
        return lower_world(desc, image_average, image_file)

    def lower(flags):
        variant = WorldDescription(desc.name)
        variant.issues, variant.output_label = desc.issues, desc.output_label
        memo = {}
        variant.aovs = _aovs_with(desc.aovs, lambda ir: ray_kinds.substitute(ir, flags, memo))
        variant.surface = ray_kinds.substitute(desc.surface, flags, memo)
        variant.volume = ray_kinds.substitute(desc.volume, flags, memo)
        return lower_world(variant, image_average, image_file)[0]

    for output in sorted(used - {"Is Camera Ray", "Is Shadow Ray"}):
        desc.issues.add(desc.output_label, "%s in the World is 0 here, as next-event estimation sees it (Cycles "
                                           "shows 1 to such rays that escape, weighed against that)" % output)
    # Next-event estimation and every ray but the camera's: no flag Cycles' world reads is set.
    params = lower(set())
    camera = lower({"camera"})
    # The AOV Outputs are written for camera rays alone: the camera look's.
    params.pop("aovs", None)
    if "aovs" in camera:
        params["aovs"] = camera.pop("aovs")
    camera = {k: v for k, v in camera.items() if k != "volume"}
    if camera != {k: v for k, v in params.items() if k not in ("volume", "aovs")}:
        params["camera"] = camera
    return params, desc.issues
