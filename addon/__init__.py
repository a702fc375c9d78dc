"""Rendezvous: a physically based render engine for Blender.

Installed layout (one folder, `rendezvous/`): this package, `shaders_map/` inside it and
`librendezvous.so` beside this file.  Run from the source tree (addon/ symlinked as
`rendezvous` into an add-ons folder), shaders_map/ is taken from the repository root and
the library from build/engine/.
"""

bl_info = {
    "name": "Rendezvous",
    "author": "Rendezvous developers",
    "version": (0, 1, 0),
    "blender": (3, 4, 0),
    "location": "Properties > Render > Render Engine > Rendezvous",
    "description": "Physically based path tracer (path tracing; BDPT and MLT to come)",
    "category": "Render",
}

import importlib.util  # noqa: E402
import os  # noqa: E402
import sys  # noqa: E402


def _load_shaders_map():
    try:
        from . import shaders_map  # installed layout
        return shaders_map
    except ImportError:
        pass
    root = os.path.dirname(os.path.dirname(os.path.realpath(__file__)))
    pkg = os.path.join(root, "shaders_map")
    name = __name__ + ".shaders_map"
    spec = importlib.util.spec_from_file_location(name, os.path.join(pkg, "__init__.py"),
                                                  submodule_search_locations=[pkg])
    if spec is None:
        raise ImportError("Rendezvous: shaders_map not found beside the add-on nor in %s" % root)
    module = importlib.util.module_from_spec(spec)
    sys.modules[name] = module
    spec.loader.exec_module(module)
    return module


shaders_map = _load_shaders_map()

_registered = []


def register():
    from . import binding, properties, engine, ui
    binding.reset()
    try:
        for module in (properties, engine, ui):
            module.register()
            _registered.append(module)
    except Exception:
        unregister()  # leave Blender as it was
        raise


def unregister():
    while _registered:
        _registered.pop().unregister()
