"""Cycles reference images kept in the repository (tests/blender/references/*.npz), so that the
Cycles comparisons with the most samples (the lamp reflections and the Cornell box: about 220 s
of Cycles rendering per test run on 2 cores) render Cycles only when what it would render changed.

A reference holds Cycles' images and the key they were rendered for: Blender's version and build,
the caller's settings (samples), and the source of every function that builds the scene or
renders it, followed through every function of this repository that they call, with the module
constants and default arguments they read. Any edit there changes the key; the test then renders
Cycles itself, compares as usual, writes the new reference next to its images and fails, naming
the file to commit (a stale reference would make every later run render Cycles again).
`--write-reference` (in the tests that use this) writes it into the source tree directly.
RDV_CYCLES_LIVE=1 ignores the references (always renders, never fails for them).

The key covers code, not files: use references only for scenes built by code alone (no image
textures, .vdb or .blend files read). A test taking a reference must still leave the scene as
rendering Cycles would have (the add-on reads Light Paths from scene.cycles).
"""

import hashlib
import inspect
import os
import sys
import types

import bpy
import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
SOURCE_DIR = os.path.join(HERE, "references")
REPOSITORY = os.path.dirname(os.path.dirname(HERE))


def _plain(value):
    """Numbers, strings and containers of them (their repr is the same in every process)."""
    if isinstance(value, (bool, int, float, str, type(None))):
        return True
    if isinstance(value, (tuple, list)):
        return all(_plain(v) for v in value)
    if isinstance(value, dict):
        return all(_plain(k) and _plain(v) for k, v in value.items())
    return False


def _in_repository(f):
    """A function of ours (the tests' and scenes' scripts), not Blender's or numpy's."""
    try:
        return os.path.abspath(inspect.getsourcefile(f)).startswith(REPOSITORY + os.sep)
    except TypeError:
        return False


def _code_names(code):
    """Global names a code object and the code nested in it (lambdas, comprehensions) read."""
    names = set(code.co_names)
    for c in code.co_consts:
        if isinstance(c, types.CodeType):
            names |= _code_names(c)
    return names


def source_closure(functions):
    """The text of the functions, of every function of this repository they call
    (transitively), of their default arguments and of the plain module constants they read."""
    parts, seen, stack = {}, set(), list(functions)
    while stack:
        f = stack.pop()
        if not inspect.isfunction(f) or f in seen:
            continue
        seen.add(f)
        module = sys.modules.get(f.__module__)
        where = os.path.basename(inspect.getsourcefile(f))  # not __module__: __main__ when run as the script
        defaults = [d if _plain(d) else type(d).__name__ for d in (f.__defaults__ or ())]
        kwdefaults = {k: d if _plain(d) else type(d).__name__ for k, d in (f.__kwdefaults__ or {}).items()}
        parts["%s:%s" % (where, f.__qualname__)] = "%s\n%r %r" % (inspect.getsource(f), defaults, kwdefaults)
        for name in sorted(_code_names(f.__code__)):
            if module is None or not hasattr(module, name):
                continue  # an attribute, a local or a builtin
            value = getattr(module, name)
            if inspect.isfunction(value) and _in_repository(value):
                stack.append(value)
            elif _plain(value):
                parts["%s:%s=" % (where, name)] = repr(value)
    return "\n".join("%s\n%s" % kv for kv in sorted(parts.items()))


def add_argument(parser):
    """--write-reference, for the test scripts that take Cycles' images from a reference."""
    parser.add_argument("--write-reference", action="store_true",
                        help="render Cycles and write its images into tests/blender/references (to commit)")


def reference_key(functions, settings):
    """The key a reference is valid for (hex digest)."""
    h = hashlib.sha256()
    h.update(("blender %s %s\n" % (bpy.app.version_string, bpy.app.build_hash.decode())).encode())
    h.update(repr(sorted(settings.items())).encode())
    h.update(source_closure(functions).encode())
    return h.hexdigest()


class Reference:
    """Cycles' images for one comparison: .images (float64 arrays), .seconds spent rendering
    them here (0 when committed), .source (the committed file, or "rendered") and .stale (a
    message naming the file to commit when the committed one did not match, else None)."""

    def __init__(self, name, functions, settings, render, out_dir, write_source=False):
        """render() -> (list of arrays, seconds) runs Cycles when there is no valid reference."""
        key = reference_key(functions, settings)
        committed = os.path.join(SOURCE_DIR, name + ".npz")
        live = os.environ.get("RDV_CYCLES_LIVE") == "1"
        self.stale = None
        if not live and not write_source:
            if os.path.exists(committed):
                with np.load(committed) as f:
                    if str(f["key"]) == key:
                        self.images = [f["image%d" % i].astype(np.float64) for i in range(int(f["count"]))]
                        self.seconds, self.source = 0.0, committed
                        return
            self.stale = "%s is missing or out of date (the scene or the Cycles settings changed)" % committed
        self.images, self.seconds = render()
        self.source = "rendered"
        fresh = os.path.join(out_dir, "references", name + ".npz")
        os.makedirs(os.path.dirname(fresh), exist_ok=True)
        for path in [fresh] + ([committed] if write_source else []):
            np.savez_compressed(path, key=np.array(key), count=np.array(len(self.images)),
                                **{"image%d" % i: np.asarray(im, np.float32) for i, im in enumerate(self.images)})
        if self.stale:
            self.stale += ": commit %s as %s" % (fresh, committed)
        print("REFERENCE %s: %s" % (name, self.stale or "written to %s" % (committed if write_source else fresh)))
