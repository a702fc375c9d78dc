"""ctypes mirror of engine/include/rendezvous.h.

Every call checks its rdv_status and raises EngineError(rdv_last_error()) on failure.
A missing or broken library raises LibraryError with a message meant for the user.
No bpy import here: the binding works in plain Python too (tests, tools).
"""

import ctypes
import json
import os
import sys

API_VERSION = 2  # RDV_API_VERSION this binding mirrors

LIB_NAMES = {"linux": "librendezvous.so", "darwin": "librendezvous.dylib", "win32": "rendezvous.dll"}

# rdv_status
RDV_OK = 0
STATUS_NAMES = {0: "OK", 1: "INVALID_ARGUMENT", 2: "UNKNOWN_PARAMETER", 3: "IO", 4: "STATE", 5: "INTERNAL", 6: "LIMIT"}

# rdv_pass
PASS_COMBINED = 0
PASS_DEPTH = 1
PASS_NORMAL = 2
PASS_ALBEDO = 3
PASS_NOISE = 4
# Cycles' light passes (session setting "light_passes"), 3 floats each
PASS_EMISSION = 5
PASS_ENVIRONMENT = 6
PASS_DIFFUSE_DIRECT = 7
PASS_DIFFUSE_INDIRECT = 8
PASS_DIFFUSE_COLOR = 9
PASS_GLOSSY_DIRECT = 10
PASS_GLOSSY_INDIRECT = 11
PASS_GLOSSY_COLOR = 12
PASS_TRANSMISSION_DIRECT = 13
PASS_TRANSMISSION_INDIRECT = 14
PASS_TRANSMISSION_COLOR = 15
PASS_VOLUME_DIRECT = 16
PASS_VOLUME_INDIRECT = 17
PASS_MIST = 18  # Cycles' data passes (rendezvous.h): 1 float each
PASS_OBJECT_INDEX = 19
PASS_MATERIAL_INDEX = 20
# Cycles' denoising data (session setting "denoising_passes"; engine/src/film/denoising_passes.h)
PASS_DENOISING_NORMAL = 21
PASS_DENOISING_ALBEDO = 22
PASS_DENOISING_DEPTH = 23
# Shadow catchers (instance setting "shadow_catcher"; engine/src/film/shadow_catcher_passes.h)
PASS_SHADOW_CATCHER = 24
PASS_SHADOW_CATCHER_MATTE = 25
# BDPT's strategy passes (session setting "strategy_passes"): PASS_STRATEGY_FIRST + k, 3 floats
# each, k numbered as engine/src/film/strategy_passes.h (addon/engine/passes.py names them)
PASS_STRATEGY_FIRST = 64
PASS_STRATEGY_LAST = 98
PASS_CHANNELS = {PASS_COMBINED: 4, PASS_DEPTH: 1, PASS_NORMAL: 3, PASS_ALBEDO: 3, PASS_NOISE: 1}
PASS_CHANNELS.update({p: 3 for p in range(PASS_EMISSION, PASS_VOLUME_INDIRECT + 1)})
PASS_CHANNELS.update({PASS_MIST: 1, PASS_OBJECT_INDEX: 1, PASS_MATERIAL_INDEX: 1})
PASS_CHANNELS.update({PASS_DENOISING_NORMAL: 3, PASS_DENOISING_ALBEDO: 3, PASS_DENOISING_DEPTH: 1})
PASS_CHANNELS.update({PASS_SHADOW_CATCHER: 3, PASS_SHADOW_CATCHER_MATTE: 4})
PASS_CHANNELS.update({p: 3 for p in range(PASS_STRATEGY_FIRST, PASS_STRATEGY_LAST + 1)})
# Shader AOVs (session setting "aovs"): the session's AOV k as PASS_AOV_COLOR_FIRST + k (RGBA)
# or PASS_AOV_VALUE_FIRST + k (1 float), by its type; at most MAX_SHADER_AOVS.
PASS_AOV_COLOR_FIRST = 100
PASS_AOV_VALUE_FIRST = 116
MAX_SHADER_AOVS = 16
PASS_CHANNELS.update({PASS_AOV_COLOR_FIRST + k: 4 for k in range(MAX_SHADER_AOVS)})
PASS_CHANNELS.update({PASS_AOV_VALUE_FIRST + k: 1 for k in range(MAX_SHADER_AOVS)})
# Cryptomatte (session setting "cryptomatte"): pass k of kind (0 object, 1 material, 2 asset) as
# PASS_CRYPTOMATTE_FIRST + CRYPTO_PASSES_PER_KIND * kind + k, RGBA (id, coverage, id, coverage).
PASS_CRYPTOMATTE_FIRST = 140
CRYPTO_PASSES_PER_KIND = 8
PASS_CHANNELS.update({PASS_CRYPTOMATTE_FIRST + k: 4 for k in range(3 * CRYPTO_PASSES_PER_KIND)})


class EngineError(RuntimeError):
    """A call into the engine failed; the message is the engine's rdv_last_error()."""

    def __init__(self, message, status=None, call=None):
        super().__init__(message)
        self.status = status
        self.call = call


class LibraryError(EngineError):
    """The engine library could not be found or loaded."""


class Progress(ctypes.Structure):
    _fields_ = [
        ("samples_done", ctypes.c_uint32),
        ("samples_target", ctypes.c_uint32),
        ("elapsed_seconds", ctypes.c_double),
        ("time_limit_seconds", ctypes.c_double),
        ("fraction_done", ctypes.c_double),
        ("rays_traced", ctypes.c_uint64),
        ("rays_per_second", ctypes.c_double),
        ("samples_dropped", ctypes.c_uint64),
        ("finished", ctypes.c_int32),
        ("cancelled", ctypes.c_int32),
        ("noise_estimate", ctypes.c_double),
        ("noise_target", ctypes.c_double),
        ("noise_reached", ctypes.c_int32),
    ]

    def as_dict(self):
        return {name: getattr(self, name) for name, _ in self._fields_}


_c_float_p = ctypes.POINTER(ctypes.c_float)
_c_uint32_p = ctypes.POINTER(ctypes.c_uint32)
_scene_p = ctypes.c_void_p
_session_p = ctypes.c_void_p
_status = ctypes.c_int

_PROTOTYPES = {
    "rdv_api_version": (ctypes.c_int, []),
    "rdv_last_error": (ctypes.c_char_p, []),
    "rdv_scene_create": (_status, [ctypes.POINTER(_scene_p)]),
    "rdv_scene_destroy": (_status, [_scene_p]),
    "rdv_scene_add_material": (_status, [_scene_p, ctypes.c_char_p, ctypes.c_char_p, _c_uint32_p]),
    "rdv_scene_add_mesh": (_status, [_scene_p, ctypes.c_char_p, ctypes.c_void_p, ctypes.c_uint32,
                                     ctypes.c_void_p, ctypes.c_void_p, ctypes.c_void_p, ctypes.c_uint32,
                                     ctypes.c_void_p, ctypes.c_uint32, _c_uint32_p]),
    "rdv_scene_add_grid": (_status, [_scene_p, ctypes.c_char_p, ctypes.c_void_p, ctypes.c_uint32, ctypes.c_uint32,
                                     ctypes.c_uint32, _c_uint32_p]),
    "rdv_scene_add_image": (_status, [_scene_p, ctypes.c_char_p, ctypes.c_void_p, ctypes.c_uint32, ctypes.c_uint32,
                                      ctypes.c_uint32, ctypes.c_char_p, _c_uint32_p]),
    "rdv_scene_add_mesh_attribute": (_status, [_scene_p, ctypes.c_uint32, ctypes.c_char_p, ctypes.c_char_p,
                                               ctypes.c_void_p, ctypes.c_uint32, ctypes.c_uint32]),
    "rdv_scene_set_material": (_status, [_scene_p, ctypes.c_uint32, ctypes.c_char_p]),
    "rdv_scene_set_mesh": (_status, [_scene_p, ctypes.c_uint32, ctypes.c_void_p, ctypes.c_uint32,
                                     ctypes.c_void_p, ctypes.c_void_p, ctypes.c_void_p, ctypes.c_uint32,
                                     ctypes.c_void_p, ctypes.c_uint32]),
    "rdv_scene_set_light": (_status, [_scene_p, ctypes.c_uint32, ctypes.c_char_p]),
    "rdv_live_objects": (_status, [_c_uint32_p, _c_uint32_p]),
    "rdv_scene_add_instance": (_status, [_scene_p, ctypes.c_uint32, ctypes.c_void_p, _c_uint32_p]),
    "rdv_scene_set_instance_transform": (_status, [_scene_p, ctypes.c_uint32, ctypes.c_void_p]),
    "rdv_scene_set_instance_params": (_status, [_scene_p, ctypes.c_uint32, ctypes.c_char_p]),
    "rdv_scene_set_instance_motion": (_status, [_scene_p, ctypes.c_uint32, ctypes.c_void_p, ctypes.c_uint32]),
    "rdv_scene_set_mesh_motion": (_status, [_scene_p, ctypes.c_uint32, ctypes.c_void_p, ctypes.c_void_p,
                                            ctypes.c_uint32, ctypes.c_uint32]),
    "rdv_scene_add_light": (_status, [_scene_p, ctypes.c_char_p, ctypes.c_char_p, _c_uint32_p]),
    "rdv_scene_set_world": (_status, [_scene_p, ctypes.c_char_p]),
    "rdv_scene_set_camera": (_status, [_scene_p, ctypes.c_char_p]),
    "rdv_scene_commit": (_status, [_scene_p]),
    "rdv_scene_messages": (_status, [_scene_p, ctypes.POINTER(ctypes.c_char_p)]),
    "rdv_scene_summary": (_status, [_scene_p, ctypes.POINTER(ctypes.c_char_p)]),
    "rdv_session_create": (_status, [_scene_p, ctypes.c_char_p, ctypes.POINTER(_session_p)]),
    "rdv_session_start": (_status, [_session_p]),
    "rdv_session_wait": (_status, [_session_p]),
    "rdv_session_cancel": (_status, [_session_p]),
    "rdv_session_destroy": (_status, [_session_p]),
    "rdv_session_progress": (_status, [_session_p, ctypes.POINTER(Progress)]),
    "rdv_session_stats": (_status, [_session_p, ctypes.POINTER(ctypes.c_char_p)]),
    "rdv_pass_channels": (ctypes.c_int, [ctypes.c_int]),
    "rdv_session_read_film": (_status, [_session_p, ctypes.c_int, ctypes.c_uint32, ctypes.c_uint32,
                                        ctypes.c_uint32, ctypes.c_uint32, ctypes.c_int32, ctypes.c_void_p]),
    "rdv_session_write_image": (_status, [_session_p, ctypes.c_char_p, ctypes.c_char_p]),
}


def _addon_dir():
    return os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def library_candidates():
    """Where the library is looked for, in order."""
    name = LIB_NAMES.get(sys.platform, "librendezvous.so")
    out = []
    env = os.environ.get("RDV_LIBRARY")
    if env:
        out.append(env)
    addon = _addon_dir()
    out.append(os.path.join(addon, name))
    # Running from the source tree (addon/ inside the repository): the build directory.
    repo = os.path.dirname(os.path.realpath(addon))
    if os.path.isfile(os.path.join(repo, "engine", "include", "rendezvous.h")):
        for build in ("build", "build-release", "build-debug"):
            out.append(os.path.join(repo, build, "engine", name))
    return out


class Library:
    """The loaded engine library with typed entry points."""

    def __init__(self, path):
        self.path = path
        try:
            # RTLD_LOCAL: keep the engine's symbols (Embree, TBB) away from Blender's own.
            self._dll = ctypes.CDLL(path, mode=getattr(os, "RTLD_LOCAL", 0) | getattr(os, "RTLD_NOW", 0))
        except OSError as exc:
            raise LibraryError("Rendezvous: the engine library %s could not be loaded: %s" % (path, exc))
        missing = []
        for fname, (restype, argtypes) in _PROTOTYPES.items():
            try:
                fn = getattr(self._dll, fname)
            except AttributeError:
                missing.append(fname)
                continue
            fn.restype = restype
            fn.argtypes = argtypes
            setattr(self, fname, fn)
        if missing:
            raise LibraryError("Rendezvous: the engine library %s is incomplete (missing %s); rebuild it"
                               % (path, ", ".join(missing)))
        version = self.rdv_api_version()
        if version != API_VERSION:
            raise LibraryError("Rendezvous: the engine library %s has API version %d but this add-on needs %d; "
                               "install the add-on and library from the same build" % (path, version, API_VERSION))
        self.version = version

    def last_error(self):
        msg = self.rdv_last_error()
        return msg.decode("utf-8", "replace") if msg else ""

    def check(self, status, call):
        if status != RDV_OK:
            msg = self.last_error() or "%s failed" % call
            raise EngineError("%s: %s (%s)" % (call, msg, STATUS_NAMES.get(status, status)), status, call)


_library = None
_library_error = None


def load(path=None, reload=False):
    """The engine library (loaded once).  Raises LibraryError with a user-facing message."""
    global _library, _library_error
    if path is not None:
        return Library(path)
    if _library is not None and not reload:
        return _library
    if _library_error is not None and not reload:
        raise LibraryError(_library_error)
    tried = []
    for cand in library_candidates():
        if os.path.isfile(cand):
            try:
                _library = Library(cand)
                _library_error = None
                return _library
            except LibraryError as exc:
                _library_error = str(exc)
                raise
        tried.append(cand)
    _library_error = ("Rendezvous: engine library not found (looked in: %s). Build the engine and install the "
                      "add-on with `cmake --build build && cmake --install build`, or set RDV_LIBRARY."
                      % ", ".join(tried))
    raise LibraryError(_library_error)


def reset():
    """Forget the cached load result (the next load() looks again)."""
    global _library, _library_error
    _library = None
    _library_error = None


def live_objects():
    """(scenes, sessions) alive in the engine library (leak checks)."""
    lib = load()
    scenes, sessions = ctypes.c_uint32(), ctypes.c_uint32()
    lib.check(lib.rdv_live_objects(ctypes.byref(scenes), ctypes.byref(sessions)), "live objects")
    return scenes.value, sessions.value


def status_message():
    """None when the library loads, else the reason (for the UI)."""
    try:
        load()
        return None
    except LibraryError as exc:
        return str(exc)


def params_json(params):
    """The JSON text (bytes) the engine receives for a parameter dict; bytes pass through
    (a caller that needs the text too serialises once)."""
    if isinstance(params, bytes):
        return params
    return json.dumps(params, allow_nan=False, separators=(",", ":")).encode("utf-8")


_json = params_json


def _ptr(arr):
    return None if arr is None else ctypes.c_void_p(arr.ctypes.data)


def _check_array(arr, dtype, name, length=None):
    import numpy as np
    if arr is None:
        return None
    if arr.dtype != dtype or not arr.flags["C_CONTIGUOUS"]:
        arr = np.ascontiguousarray(arr, dtype=dtype)
    if length is not None and arr.size != length:
        raise EngineError("%s: expected %d values, got %d" % (name, length, arr.size))
    return arr


def _matrix16(m):
    m = list(m)
    if len(m) == 4:  # rows
        m = [float(x) for row in m for x in row]
    if len(m) != 16:
        raise EngineError("a transform needs 16 numbers")
    return (ctypes.c_float * 16)(*[float(x) for x in m])


class _Handle:
    """Owns one engine handle: closed explicitly, by `with`, or when collected."""
    _destroy = None  # name of the rdv_*_destroy function

    handle = None

    def close(self):
        if self.handle:
            getattr(self.lib, self._destroy)(self.handle)
            self.handle = None

    __del__ = close

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()


class Scene(_Handle):
    _destroy = "rdv_scene_destroy"
    """An engine scene.  Use as a context manager or call close()."""

    handle = None

    def __init__(self, lib=None):
        self.lib = lib or load()
        h = _scene_p()
        self.lib.check(self.lib.rdv_scene_create(ctypes.byref(h)), "rdv_scene_create")
        self.handle = h

    def add_material(self, name, params):
        out = ctypes.c_uint32()
        self.lib.check(self.lib.rdv_scene_add_material(self.handle, name.encode("utf-8"), _json(params),
                                                       ctypes.byref(out)), "material '%s'" % name)
        return out.value

    def set_material(self, material, params):
        """Replaces material `material` in place (no session may exist)."""
        self.lib.check(self.lib.rdv_scene_set_material(self.handle, int(material), _json(params)),
                       "material %d" % material)

    def add_grid(self, name, values, resolution):
        """A dense grid as a binary buffer: values (nx*ny*nz,) float32, x fastest; a medium
        names it {"buffer": name, "bounds": ...}.  Adding a name again replaces it."""
        import numpy as np
        nx, ny, nz = (int(x) for x in resolution)
        values = _check_array(values, np.float32, "grid '%s'" % name, nx * ny * nz)
        out = ctypes.c_uint32()
        self.lib.check(self.lib.rdv_scene_add_grid(self.handle, name.encode("utf-8"), _ptr(values), nx, ny, nz,
                                                   ctypes.byref(out)), "grid '%s'" % name)
        return out.value

    def add_image(self, name, pixels, width, height, channels, colorspace=""):
        """An image as a binary buffer: pixels (width*height*channels,) float32, bottom row
        first, in `colorspace`; an image texture node names it {"buffer": name}.  Adding a
        name again replaces it."""
        import numpy as np
        w, h, c = int(width), int(height), int(channels)
        pixels = _check_array(pixels, np.float32, "image '%s'" % name, w * h * c)
        out = ctypes.c_uint32()
        self.lib.check(self.lib.rdv_scene_add_image(self.handle, name.encode("utf-8"), _ptr(pixels), w, h, c,
                                                    (colorspace or "").encode("utf-8"), ctypes.byref(out)),
                       "image '%s'" % name)
        return out.value

    def set_light(self, light, params):
        self.lib.check(self.lib.rdv_scene_set_light(self.handle, int(light), _json(params)), "light %d" % light)

    def set_mesh(self, mesh, positions, indices, normals=None, uvs=None, material_ids=None, default_material=0,
                 attributes=None):
        """Replaces mesh `mesh`'s geometry in place (same arrays as add_mesh; attributes are added again)."""
        return self.add_mesh(None, positions, indices, normals, uvs, material_ids, default_material, replace=mesh,
                             attributes=attributes)

    def add_mesh_attribute(self, mesh, name, kind, data, components):
        """A named per-vertex UV map (kind "uv", 2 components) or colour ("color", 3 or 4)."""
        import numpy as np
        data = _check_array(data, np.float32, "attribute '%s'" % name)
        nv = data.size // int(components)
        self.lib.check(self.lib.rdv_scene_add_mesh_attribute(
            self.handle, int(mesh), name.encode("utf-8"), kind.encode("utf-8"), _ptr(data), int(components), nv),
            "mesh %d attribute '%s'" % (mesh, name))

    def add_mesh(self, name, positions, indices, normals=None, uvs=None, material_ids=None,
                 default_material=0, replace=None, attributes=None):
        """positions (V,3) float32, indices (T,3) uint32; normals (V,3), uvs (V,2), material_ids (T,);
        attributes: [(name, "uv"|"color", data (V*components,), components)]."""
        mid = self._add_mesh(name, positions, indices, normals, uvs, material_ids, default_material, replace)
        for aname, kind, data, comps in attributes or ():
            self.add_mesh_attribute(mid, aname, kind, data, comps)
        return mid

    def _add_mesh(self, name, positions, indices, normals, uvs, material_ids, default_material, replace):
        import numpy as np
        positions = _check_array(positions, np.float32, "positions")
        nv = positions.size // 3
        indices = _check_array(indices, np.uint32, "indices")
        nt = indices.size // 3
        normals = _check_array(normals, np.float32, "normals", nv * 3)
        uvs = _check_array(uvs, np.float32, "uvs", nv * 2)
        material_ids = _check_array(material_ids, np.uint32, "material_ids", nt)
        if replace is not None:
            self.lib.check(self.lib.rdv_scene_set_mesh(
                self.handle, int(replace), _ptr(positions), nv, _ptr(normals), _ptr(uvs), _ptr(indices), nt,
                _ptr(material_ids), int(default_material)), "mesh %d" % replace)
            return int(replace)
        out = ctypes.c_uint32()
        self.lib.check(self.lib.rdv_scene_add_mesh(
            self.handle, name.encode("utf-8"), _ptr(positions), nv, _ptr(normals), _ptr(uvs), _ptr(indices), nt,
            _ptr(material_ids), int(default_material), ctypes.byref(out)), "mesh '%s'" % name)
        return out.value

    def add_instance(self, mesh, transform):
        out = ctypes.c_uint32()
        self.lib.check(self.lib.rdv_scene_add_instance(self.handle, int(mesh), _matrix16(transform),
                                                       ctypes.byref(out)), "instance of mesh %d" % mesh)
        return out.value

    def set_instance_transform(self, instance, transform):
        self.lib.check(self.lib.rdv_scene_set_instance_transform(self.handle, int(instance), _matrix16(transform)),
                       "instance %d" % instance)

    def set_instance_params(self, instance, params):
        self.lib.check(self.lib.rdv_scene_set_instance_params(self.handle, int(instance), _json(params)),
                       "instance %d" % instance)

    def set_instance_motion(self, instance, matrices):
        """Motion blur: the instance's transforms (16 row-major numbers each) at evenly spaced
        times over the open shutter."""
        import numpy as np
        arr = np.ascontiguousarray(matrices, dtype=np.float32).reshape(-1)
        if arr.size % 16:
            raise EngineError("instance %d: motion steps need 16 numbers each, got %d" % (instance, arr.size))
        steps = arr.size // 16
        self.lib.check(self.lib.rdv_scene_set_instance_motion(self.handle, int(instance), _ptr(arr), steps),
                       "instance %d" % instance)

    def set_mesh_motion(self, mesh, positions, normals=None):
        """Deformation blur: the mesh's vertex positions (and normals, or None) at evenly spaced
        times over the open shutter, one (V*3,) float32 array per step."""
        import numpy as np
        pos = np.ascontiguousarray(np.concatenate([np.asarray(p, np.float32).reshape(-1) for p in positions]))
        steps = len(positions)
        nv = pos.size // (3 * steps) if steps else 0
        nrm = None
        if normals is not None:
            nrm = np.ascontiguousarray(np.concatenate([np.asarray(n, np.float32).reshape(-1) for n in normals]))
            if nrm.size != pos.size:
                raise EngineError("mesh %d: deformation normals and positions differ in size" % mesh)
        self.lib.check(self.lib.rdv_scene_set_mesh_motion(self.handle, int(mesh), _ptr(pos),
                                                          None if nrm is None else _ptr(nrm), nv, steps),
                       "mesh %d" % mesh)

    def add_light(self, name, params):
        out = ctypes.c_uint32()
        self.lib.check(self.lib.rdv_scene_add_light(self.handle, name.encode("utf-8"), _json(params),
                                                    ctypes.byref(out)), "light '%s'" % name)
        return out.value

    def set_world(self, params):
        self.lib.check(self.lib.rdv_scene_set_world(self.handle, _json(params)), "world")

    def set_camera(self, params):
        self.lib.check(self.lib.rdv_scene_set_camera(self.handle, _json(params)), "camera")

    def commit(self):
        self.lib.check(self.lib.rdv_scene_commit(self.handle), "scene commit")

    def messages(self):
        out = ctypes.c_char_p()
        self.lib.check(self.lib.rdv_scene_messages(self.handle, ctypes.byref(out)), "scene messages")
        text = out.value.decode("utf-8", "replace") if out.value else ""
        return [line for line in text.splitlines() if line.strip()]

    def summary(self):
        out = ctypes.c_char_p()
        self.lib.check(self.lib.rdv_scene_summary(self.handle, ctypes.byref(out)), "scene summary")
        try:
            return json.loads(out.value.decode("utf-8")) if out.value else {}
        except ValueError:
            return {"raw": out.value.decode("utf-8", "replace")}


class Session(_Handle):
    _destroy = "rdv_session_destroy"
    handle = None

    def __init__(self, scene, settings):
        self.lib = scene.lib
        self.scene = scene  # keep the scene alive while the session exists
        h = _session_p()
        self.lib.check(self.lib.rdv_session_create(scene.handle, _json(settings), ctypes.byref(h)),
                       "session settings")
        self.handle = h
        self._progress = Progress()

    def start(self):
        self.lib.check(self.lib.rdv_session_start(self.handle), "session start")

    def wait(self):
        self.lib.check(self.lib.rdv_session_wait(self.handle), "session wait")

    def cancel(self):
        self.lib.check(self.lib.rdv_session_cancel(self.handle), "session cancel")

    def progress(self):
        self.lib.check(self.lib.rdv_session_progress(self.handle, ctypes.byref(self._progress)), "session progress")
        return self._progress

    def stats(self):
        """The integrator's own figures as a dict (Metropolis: acceptance, chains, b; {} otherwise)."""
        text = ctypes.c_char_p()
        self.lib.check(self.lib.rdv_session_stats(self.handle, ctypes.byref(text)), "session stats")
        return json.loads(text.value.decode("utf-8")) if text.value else {}

    def read_film(self, pass_, x, y, width, height, out, top_down=False):
        """Fills `out` (C-contiguous float32 with width*height*channels values)."""
        need = width * height * PASS_CHANNELS[pass_]
        if out.dtype.name != "float32" or not out.flags["C_CONTIGUOUS"] or out.size != need:
            raise EngineError("read_film: output must be C-contiguous float32 with %d values" % need)
        self.lib.check(self.lib.rdv_session_read_film(self.handle, int(pass_), x, y, width, height,
                                                      1 if top_down else 0, ctypes.c_void_p(out.ctypes.data)),
                       "read film")
        return out

    def write_image(self, path, view=None):
        self.lib.check(self.lib.rdv_session_write_image(self.handle, path.encode("utf-8"),
                                                        view.encode("utf-8") if view else None), "write image")
