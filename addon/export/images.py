"""bpy images -> what the engine reads for image and environment texture nodes.

Single images on disk are passed by absolute path; packed images are written once per
session to a temporary directory; an image sequence gives the file of the frame its
Image User shows (Blender's frame start / offset / cyclic rules); a movie its file and
frame (OpenImageIO reads the frame); UDIM tiles the file pattern with <UDIM> and the tile
numbers. Images without a file (generated, painted and never saved, made by a script)
give BUFFER: the exporter sends their pixels to the engine (image_pixels).
"""

import hashlib
import os
import re
import tempfile

import numpy as np

BUFFER = "buffer"

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


def _abspath(image):
    import bpy
    return os.path.normpath(bpy.path.abspath(image.filepath, library=image.library))


def image_file(image):
    """An absolute path to a file holding `image` (a single image), or None."""
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
                p = _abspath(image)
                path = p if os.path.isfile(p) else None
    except Exception:
        path = None
    _cache[key] = path
    return path


def user_frame(image_user, frame):
    """The image frame an Image User shows at scene frame `frame` (Blender's
    BKE_image_user_frame_get: frame start, duration, cyclic, then the offset)."""
    length = int(image_user.frame_duration)
    if length == 0:
        return 0
    cfra = int(frame) - int(image_user.frame_start) + 1
    cyclic = bool(image_user.use_cyclic)
    if cyclic:
        cfra %= length
        if cfra == 0:
            cfra = length
    cfra = min(max(cfra, 0), length)
    if cyclic:
        cfra %= length
        if cfra == 0:
            cfra = length
    return cfra + int(image_user.frame_offset)


def sequence_path(path, number):
    """`path` with its frame number (the last run of digits in the file name, before the
    extension) replaced by `number`, padded to the same width (BLI_path_sequence_*)."""
    head, name = os.path.split(path)
    dot = name.rfind(".")
    stem, ext = (name[:dot], name[dot:]) if dot > 0 else (name, "")
    m = re.search(r"(\d+)(\D*)$", stem)
    if m is None:
        return path
    digits = len(m.group(1))
    return os.path.join(head, stem[:m.start(1)] + "%0*d" % (digits, max(number, 0)) + m.group(2) + ext)


def image_source(image, image_user=None, frame=1):
    """What the engine reads for `image` as an Image User shows it at scene frame `frame`:
    a path (str), a dict ({"file": path[, "frame": n | "tiles": [...]]}), BUFFER (send
    image_pixels), or None (nothing readable: the caller keeps the average colour)."""
    if image is None:
        return None
    source = image.source
    if source == "FILE":
        path = image_file(image)
        if path is None and getattr(image, "packed_file", None) is not None and image.has_data:
            return BUFFER  # packed without data to write: Blender's pixels
        return path
    if source == "GENERATED":
        return BUFFER
    if source in ("SEQUENCE", "MOVIE"):
        if getattr(image, "packed_file", None) is not None:
            return None
        number = user_frame(image_user, frame) if image_user is not None else 1
        path = _abspath(image)
        # A frame without a file renders magenta with a warning, as in Cycles.
        if source == "SEQUENCE":
            return {"file": sequence_path(path, number)}
        # A movie's frames are numbered from 1 in Blender, subimages from 0 in OIIO.
        return {"file": path, "frame": max(number, 1) - 1}
    if source == "TILED":
        if getattr(image, "packed_file", None) is not None or "<UDIM>" not in image.filepath:
            return None
        tiles = [int(t.number) for t in image.tiles]  # one without a file renders magenta
        return {"file": _abspath(image), "tiles": tiles} if tiles else None
    return None


def image_pixels(image):
    """(pixels, width, height, channels, colorspace) of an image in memory: float32 in
    Blender's layout (bottom row first), straight alpha, in the colour space the engine
    converts from. Byte images' values are in their colour space (sRGB for a painted
    texture); float images are scene-linear already (Cycles reads them as they are)."""
    w, h = int(image.size[0]), int(image.size[1])
    ch = int(image.channels)
    if w <= 0 or h <= 0 or ch <= 0 or ch > 4:
        return None
    px = np.empty(w * h * ch, dtype=np.float32)
    image.pixels.foreach_get(px)
    if image.is_float:
        if ch == 4:  # float buffers hold premultiplied colour; the engine takes straight
            rgba = px.reshape(-1, 4)
            a = rgba[:, 3:4]
            np.divide(rgba[:, :3], a, out=rgba[:, :3], where=(a > 0) & (a != 1))
        space = "Linear"
    else:
        space = getattr(image.colorspace_settings, "name", "") or "sRGB"
    return px, w, h, ch, space


def pixels_digest(pixels):
    """A digest of an image's pixels (to skip re-sending an unchanged one)."""
    return hashlib.blake2b(memoryview(np.ascontiguousarray(pixels, np.float32)).cast("B"), digest_size=16).digest()


def clear_cache():
    _cache.clear()
