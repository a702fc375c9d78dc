"""bpy images -> files the engine can read (for image and environment texture nodes).

Single images on disk are passed by absolute path; packed images are written once per
session to a temporary directory.  Generated, sequence, movie and UDIM images give None:
shaders_map then uses the image's average colour, with a warning.
"""

import os
import tempfile

_packed_dir = None
_cache = {}


def _packed_path(image):
    global _packed_dir
    pf = image.packed_file
    data = getattr(pf, "data", None)
    if not data:
        return None
    if _packed_dir is None:
        _packed_dir = tempfile.mkdtemp(prefix="rendezvous_images_")
    base = os.path.basename(getattr(image, "filepath", "") or "") or (image.name + ".png")
    safe = "".join(c if c.isalnum() or c in "._-" else "_" for c in base)
    path = os.path.join(_packed_dir, "%x_%s" % (abs(hash(image.name_full)) & 0xFFFFFFFF, safe))
    if not os.path.exists(path):
        with open(path, "wb") as f:
            f.write(bytes(data))
    return path


def image_file(image):
    """An absolute path to a file holding `image`, or None."""
    if image is None:
        return None
    key = (getattr(image, "name_full", image.name), getattr(image, "filepath", ""))
    if key in _cache:
        return _cache[key]
    path = None
    try:
        if image.source == "FILE":
            if getattr(image, "packed_file", None) is not None:
                path = _packed_path(image)
            else:
                import bpy
                p = bpy.path.abspath(image.filepath, library=image.library)
                p = os.path.normpath(p)
                path = p if os.path.isfile(p) else None
    except Exception:
        path = None
    _cache[key] = path
    return path


def clear_cache():
    _cache.clear()
