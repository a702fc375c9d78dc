"""Average colour of a Blender image (scene-linear), for lowering textures to constants."""

import os

import numpy as np

_SRGB_NAMES = ("sRGB",)
_cache = {}


def _srgb_to_linear(c):
    return np.where(c <= 0.04045, c / 12.92, ((c + 0.055) / 1.055) ** 2.4)


def image_missing(image):
    if image is None:
        return True
    if getattr(image, "packed_file", None) is not None:
        return False
    if image.source in ("GENERATED", "VIEWER"):
        return False
    try:
        import bpy
        path = bpy.path.abspath(image.filepath, library=image.library)
    except Exception:
        path = image.filepath
    if image.source == "TILED":
        return False
    return not os.path.exists(path)


def image_average(image):
    """((r, g, b), alpha) in scene-linear, or "missing" when the file cannot be found."""
    key = (image.name_full if hasattr(image, "name_full") else image.name, getattr(image, "filepath", ""))
    if key in _cache:
        return _cache[key]
    if image_missing(image):
        _cache[key] = "missing"
        return "missing"
    w, h = image.size[0], image.size[1]
    ch = image.channels
    if w == 0 or h == 0 or ch == 0:
        _cache[key] = "missing"
        return "missing"
    px = np.empty(w * h * ch, dtype=np.float32)
    image.pixels.foreach_get(px)
    px = px.reshape(-1, ch)
    rgb = px[:, :3] if ch >= 3 else np.repeat(px[:, :1], 3, axis=1)
    space = getattr(image.colorspace_settings, "name", "")
    if not image.is_float and space in _SRGB_NAMES:
        rgb = _srgb_to_linear(rgb)
    mean = rgb.mean(axis=0, dtype=np.float64)
    alpha = float(px[:, 3].mean()) if ch >= 4 else 1.0
    result = (tuple(float(x) for x in mean), alpha)
    _cache[key] = result
    return result


def clear_cache():
    _cache.clear()
