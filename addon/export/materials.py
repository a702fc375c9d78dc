"""Materials actually used by exported meshes -> engine materials, once each."""

from .. import shaders_map
from ..utils import blender_version

DEFAULT_NAME = "__rendezvous_default"


class MaterialCache:
    def __init__(self, sink, messages, image_average=None, image_file=None):
        self.sink = sink
        self.messages = messages
        self.image_average = image_average
        self.image_file = image_file
        self._ids = {}
        self._names = set()
        self._default = None

    def default(self):
        if self._default is None:
            self._default = self.sink.add_material(DEFAULT_NAME, dict(shaders_map.DEFAULT_SURFACE))
        return self._default

    def get(self, material):
        if material is None:
            return self.default()
        key = getattr(material, "name_full", material.name)
        mid = self._ids.get(key)
        if mid is not None:
            return mid
        try:
            params, warning = shaders_map.convert_material(material, image_average=self.image_average,
                                                           image_file=self.image_file,
                                                           blender_version=blender_version())
        except Exception as exc:  # a bug in a node handler must not stop the render
            params, warning = dict(shaders_map.DEFAULT_SURFACE), "Material '%s': translation failed (%s: %s)" % (
                key, type(exc).__name__, exc)
        if warning:
            self.messages.warn(warning)
        name = key
        n = 1
        while name in self._names:
            n += 1
            name = "%s#%d" % (key, n)
        self._names.add(name)
        mid = self.sink.add_material(name, params)
        self._ids[key] = mid
        return mid
