"""Small helpers shared by the add-on modules (no bpy import at module level)."""

import math

try:
    import numpy as np
except ImportError:  # pragma: no cover - Blender always ships numpy
    np = None


def blender_version():
    try:
        import bpy
        return tuple(bpy.app.version)
    except ImportError:
        return (3, 4, 0)


def matrix_rows(m):
    """A 4x4 mathutils.Matrix (or nested rows) -> 16 floats, row-major."""
    return [float(m[i][j]) for i in range(4) for j in range(4)]


def matrix_array(m):
    return np.array(matrix_rows(m), dtype=np.float32).reshape(4, 4)


def normalize_frame(m16):
    """Removes scale from a row-major 4x4 (columns 0..2 normalised).

    Returns (matrix16 without scale, (sx, sy, sz) column lengths)."""
    m = [list(m16[i * 4:(i + 1) * 4]) for i in range(4)]
    scales = []
    for c in range(3):
        length = math.sqrt(sum(m[r][c] ** 2 for r in range(3)))
        scales.append(length)
        if length > 0.0:
            for r in range(3):
                m[r][c] /= length
    return [x for row in m for x in row], tuple(scales)


def determinant3(m16):
    a = m16
    return (a[0] * (a[5] * a[10] - a[6] * a[9]) - a[1] * (a[4] * a[10] - a[6] * a[8])
            + a[2] * (a[4] * a[9] - a[5] * a[8]))


def is_finite_matrix(m16):
    return all(math.isfinite(x) for x in m16)


def rgb(v):
    return [float(v[0]), float(v[1]), float(v[2])]


class Messages:
    """Warnings gathered during an export, de-duplicated, in order."""

    def __init__(self):
        self.lines = []
        self._seen = set()

    def warn(self, text):
        if text and text not in self._seen:
            self._seen.add(text)
            self.lines.append(text)

    def extend(self, lines):
        for line in lines:
            self.warn(line)

    def drop(self, prefixes):
        """Forgets the warnings that start with any of `prefixes` (a tuple), e.g. an object's
        before it is exported again."""
        gone = [line for line in self.lines if line.startswith(prefixes)]
        if gone:
            self.lines[:] = [line for line in self.lines if not line.startswith(prefixes)]
            self._seen.difference_update(gone)
