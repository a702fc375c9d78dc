"""Materials actually used by exported meshes -> engine materials, once each.

A material whose look depends on the kind of ray (Light Path's ray types, shaders_map/
ray_kinds.py) becomes one engine material per look, each with the kinds of ray that see it
(`looks`); the exporter sends the objects using it once per look (export/__init__.py)."""

from .. import shaders_map
from ..utils import blender_version

DEFAULT_NAME = "__rendezvous_default"
CRYPTOMATTE_DEFAULT = "default_surface"  # Cycles' name for the surface of objects without a material


class MaterialCache:
    def __init__(self, sink, messages, image_average=None, image_file=None, cryptomatte=False,
                 view_layer_attribute=None):
        """cryptomatte: name each engine material after its Blender material ("cryptomatte").
        view_layer_attribute: what Attribute nodes of type View Layer read (shaders_map)."""
        self.view_layer_attribute = view_layer_attribute
        self.sink = sink
        self.cryptomatte = cryptomatte
        self.messages = messages
        self.image_average = image_average
        self.image_file = image_file
        self._ids = {}  # material name -> engine id (of the look diffuse rays see)
        self._looks = {}  # material name -> [(kinds or None, engine id)]
        self._names = set()
        self._default = None

    def default(self):
        if self._default is None:
            params = dict(shaders_map.DEFAULT_SURFACE)
            if self.cryptomatte:
                params["cryptomatte"] = CRYPTOMATTE_DEFAULT
            self._default = self.sink.add_material(DEFAULT_NAME, params)
        return self._default

    def get(self, material):
        """The engine material (of a material with several looks: the one diffuse rays see)."""
        if material is None:
            return self.default()
        key = getattr(material, "name_full", material.name)
        if key not in self._ids:
            self.looks(material)
        return self._ids[key]

    def looks(self, material):
        """[(kinds, engine id)]: kinds None for a material every ray sees alike."""
        if material is None:
            return [(None, self.default())]
        key = getattr(material, "name_full", material.name)
        if key in self._looks:
            return self._looks[key]
        try:
            variants, warning = shaders_map.convert_material_variants(material, image_average=self.image_average,
                                                                      view_layer_attribute=self.view_layer_attribute,
                                                                      image_file=self.image_file,
                                                                      blender_version=blender_version())
        except Exception as exc:  # a bug in a node handler must not stop the render
            variants, warning = [(None, dict(shaders_map.DEFAULT_SURFACE))], \
                "Material '%s': translation failed (%s: %s)" % (key, type(exc).__name__, exc)
        if warning:
            self.messages.warn(warning)
        looks = []
        for kinds, params in variants:
            base = key if kinds is None else "%s [%s]" % (key, ", ".join(kinds))
            name, n = base, 1
            while name in self._names:
                n += 1
                name = "%s#%d" % (base, n)
            self._names.add(name)
            if self.cryptomatte:  # every look shows as its material (Cycles' shader name)
                params = dict(params, cryptomatte=material.name)
            looks.append((kinds, self.sink.add_material(name, params)))
        self._looks[key] = looks
        self._ids[key] = shaders_map.ray_kinds.lighting_look(looks)
        return looks


def ray_kind_cells(looks_per_slot):
    """The groups of ray kinds an object's copies are seen by, from its slots' looks
    (MaterialCache.looks each): [(kinds or None, engine material id per slot)]. One entry
    with kinds None when every slot looks alike to every ray."""
    if all(len(looks) == 1 for looks in looks_per_slot):
        return [(None, [looks[0][1] for looks in looks_per_slot])]
    cells = []
    for kind in shaders_map.ray_kinds.KINDS:
        ids = [next(mid for kinds, mid in looks if kinds is None or kind in kinds) for looks in looks_per_slot]
        for cell_kinds, cell_ids in cells:
            if cell_ids == ids:
                cell_kinds.append(kind)
                break
        else:
            cells.append(([kind], ids))
    return cells
