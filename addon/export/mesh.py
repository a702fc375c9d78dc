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


DEFAULT_COLOR_ATTRIBUTE = "__rdv_default_color"  # = shaders_map.DEFAULT_COLOR_ATTRIBUTE


class MeshArrays:
    __slots__ = ("positions", "normals", "uvs", "indices", "slot_indices", "num_nonfinite", "num_vertices",
                 "num_triangles", "attributes")

    def __init__(self, positions, normals, uvs, indices, slot_indices, num_nonfinite=0, attributes=None):
        self.attributes = attributes or []  # [(name, "uv"|"color", float32 data per engine vertex, components)]
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


def _default_color_name(me):
    cas = getattr(me, "color_attributes", None)
    if cas is None or len(cas) == 0:
        return None
    idx = getattr(cas, "render_color_index", -1)
    if idx is not None and 0 <= idx < len(cas):
        return cas[idx].name
    active = getattr(cas, "active_color", None)
    return active.name if active is not None else cas[0].name


def _corner_attributes(me, names, n_loops, loop_vi, npoly):
    """Named UV maps / colour / generic attributes as per-corner float32 arrays."""
    out = []
    loop_poly = None
    for name in names:
        real = _default_color_name(me) if name == DEFAULT_COLOR_ATTRIBUTE else name
        if not real:
            continue
        layers = getattr(me, "uv_layers", None)
        if layers is not None and name != DEFAULT_COLOR_ATTRIBUTE and layers.get(real) is not None:
            out.append((name, "uv", _get(layers[real].data, "uv", n_loops, np.float32, 2), 2))
            continue
        attrs = getattr(me, "attributes", None)
        attr = attrs.get(real) if attrs is not None else None
        if attr is None:
            continue
        dt = attr.data_type
        if dt in ("FLOAT_COLOR", "BYTE_COLOR"):
            width, prop, kind = 4, "color", "color"
        elif dt == "FLOAT_VECTOR":
            width, prop, kind = 3, "vector", "color"
        elif dt == "FLOAT2":
            width, prop, kind = 2, "vector", "uv"
        elif dt in ("FLOAT", "INT", "BOOLEAN"):
            width, prop, kind = 1, "value", "color"
        else:
            continue
        n = len(attr.data)
        data = _get(attr.data, prop, n, np.float32, width).reshape(n, width)
        if attr.domain == "CORNER":
            pass
        elif attr.domain == "POINT":
            data = data[loop_vi]
        elif attr.domain == "FACE":
            if loop_poly is None:
                loop_poly = np.repeat(np.arange(npoly, dtype=np.uint32),
                                      _get(me.polygons, "loop_total", npoly, np.uint32))
            data = data[loop_poly]
        else:
            continue
        if width == 1:
            data = np.repeat(data, 3, axis=1)
            width = 3
        out.append((name, kind, np.ascontiguousarray(data, dtype=np.float32).reshape(-1), width))
    return out


def mesh_arrays(me, need_uvs=False, uv_name=None, attributes=()):
    """me: an evaluated bpy.types.Mesh (e.g. from Object.to_mesh()). Returns MeshArrays or None
    when the mesh has no triangles.  attributes: names of UV maps / colour attributes the
    materials read (shaders_map's DEFAULT_COLOR_ATTRIBUTE = the default colour attribute)."""
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

    if uv_layer is None and not split and (all_flat or all_smooth) and not attributes:
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
    attrs = _corner_attributes(me, attributes, n_loops, loop_vi, npoly) if attributes else []
    return MeshArrays(positions, np.ascontiguousarray(normals, dtype=np.float32), uvs, tri_loops, slot_indices,
                      num_nonfinite, attrs)
