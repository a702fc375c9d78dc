"""Evaluated Blender meshes -> flat numpy arrays for rdv_scene_add_mesh.

No per-vertex Python: everything goes through foreach_get into preallocated arrays
(uint32 for index buffers, which is several times faster than int32 in Blender 3.4)
and numpy gathers.

Vertex layout:
* all faces flat, no UVs needed  -> Blender's vertices, no normals (the engine shades flat);
* all faces smooth, no custom/split normals, no UVs -> Blender's vertices + vertex normals;
* otherwise (mixed smooth/flat, auto smooth, custom normals, UVs) -> one engine vertex per
  face corner (loop), with per-corner normals/UVs.
"""

import numpy as np


class MeshArrays:
    __slots__ = ("positions", "normals", "uvs", "indices", "slot_indices", "num_nonfinite", "num_vertices",
                 "num_triangles")

    def __init__(self, positions, normals, uvs, indices, slot_indices, num_nonfinite=0):
        self.positions = positions
        self.normals = normals
        self.uvs = uvs
        self.indices = indices
        self.slot_indices = slot_indices
        self.num_nonfinite = num_nonfinite
        self.num_vertices = len(positions) // 3
        self.num_triangles = len(indices) // 3


def _get(collection, attr, n, dtype, width=1):
    arr = np.empty(n * width, dtype=dtype)
    if n:
        collection.foreach_get(attr, arr)
    return arr


def _has_legacy_split_normals(me):
    # Blender < 4.1: use_auto_smooth / custom split normals need calc_normals_split().
    return getattr(me, "use_auto_smooth", False) or getattr(me, "has_custom_normals", False)


def _corner_normals(me, n_loops):
    """Per-loop normals, 3.x and 4.1+."""
    if hasattr(me, "corner_normals"):  # 4.1+
        return _get(me.corner_normals, "vector", n_loops, np.float32, 3)
    me.calc_normals_split()
    return _get(me.loops, "normal", n_loops, np.float32, 3)


def _vertex_normals(me, nv):
    if hasattr(me, "vertex_normals"):  # 3.5+
        return _get(me.vertex_normals, "vector", nv, np.float32, 3)
    return _get(me.vertices, "normal", nv, np.float32, 3)


def _polygon_normals(me, npoly):
    if hasattr(me, "polygon_normals"):  # 3.5+
        return _get(me.polygon_normals, "vector", npoly, np.float32, 3)
    return _get(me.polygons, "normal", npoly, np.float32, 3)


def _smooth_flags(me, npoly):
    sharp = None
    attrs = getattr(me, "attributes", None)
    if attrs is not None and "sharp_face" in attrs and hasattr(me, "normals_domain"):  # 4.1+
        sharp = _get(attrs["sharp_face"].data, "value", npoly, bool)
        return ~sharp
    return _get(me.polygons, "use_smooth", npoly, bool)


def _uv_layer(me, uv_name):
    layers = getattr(me, "uv_layers", None)
    if not layers or len(layers) == 0:
        return None
    if uv_name:
        layer = layers.get(uv_name)
        if layer is not None:
            return layer
    for layer in layers:
        if getattr(layer, "active_render", False):
            return layer
    return layers.active


def mesh_arrays(me, need_uvs=False, uv_name=None):
    """me: an evaluated bpy.types.Mesh (e.g. from Object.to_mesh()). Returns MeshArrays or None
    when the mesh has no triangles."""
    me.calc_loop_triangles()
    nt = len(me.loop_triangles)
    if nt == 0:
        return None
    nv = len(me.vertices)
    n_loops = len(me.loops)
    npoly = len(me.polygons)

    co = _get(me.vertices, "co", nv, np.float32, 3)
    tri_loops = _get(me.loop_triangles, "loops", nt, np.uint32, 3)
    tri_poly = _get(me.loop_triangles, "polygon_index", nt, np.uint32)
    poly_mat = _get(me.polygons, "material_index", npoly, np.uint32)
    slot_indices = poly_mat[tri_poly] if npoly else np.zeros(nt, np.uint32)

    bad = ~np.isfinite(co)
    num_nonfinite = int(np.count_nonzero(bad.reshape(-1, 3).any(axis=1))) if bad.any() else 0

    smooth = _smooth_flags(me, npoly)
    all_smooth = bool(smooth.all()) if npoly else True
    all_flat = not bool(smooth.any()) if npoly else False
    domain = getattr(me, "normals_domain", None)  # 4.1+: 'POINT', 'FACE' or 'CORNER'
    if domain is not None:
        split = domain == "CORNER"
        all_smooth = domain == "POINT"
        all_flat = domain == "FACE"
    else:
        split = _has_legacy_split_normals(me)

    uv_layer = _uv_layer(me, uv_name) if need_uvs else None

    if uv_layer is None and not split and (all_flat or all_smooth):
        loop_vi = _get(me.loops, "vertex_index", n_loops, np.uint32)
        indices = loop_vi[tri_loops]
        normals = None if all_flat else _vertex_normals(me, nv)
        return MeshArrays(co, normals, None, indices, slot_indices, num_nonfinite)

    # One engine vertex per face corner.
    loop_vi = _get(me.loops, "vertex_index", n_loops, np.uint32)
    positions = co.reshape(-1, 3)[loop_vi].reshape(-1)
    if split:
        normals = _corner_normals(me, n_loops)
    else:
        vn = _vertex_normals(me, nv).reshape(-1, 3)
        normals = vn[loop_vi]
        if not all_smooth:
            loop_poly = np.repeat(np.arange(npoly, dtype=np.uint32),
                                  _get(me.polygons, "loop_total", npoly, np.uint32))
            pn = _polygon_normals(me, npoly).reshape(-1, 3)
            flat_loops = ~smooth[loop_poly]
            normals[flat_loops] = pn[loop_poly[flat_loops]]
        normals = normals.reshape(-1)
    uvs = _get(uv_layer.data, "uv", n_loops, np.float32, 2) if uv_layer is not None else None
    return MeshArrays(positions, np.ascontiguousarray(normals, dtype=np.float32), uvs, tri_loops, slot_indices,
                      num_nonfinite)
