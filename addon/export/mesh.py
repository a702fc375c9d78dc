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

from .. import shaders_map


DEFAULT_COLOR_ATTRIBUTE = "__rdv_default_color"  # = shaders_map.DEFAULT_COLOR_ATTRIBUTE
# Geometry > Pointiness and Random Per Island, which Cycles derives from the mesh: computed here
# (geometry_attribute) and sent as per-vertex attributes under these names (= shaders_map's).
# Blender's MikkTSpace tangents of the default UV map and their bitangent signs, per corner
# (x, y, z, sign), for tangent-space Normal Maps as Cycles applies them (the engine's name).
TANGENT_ATTRIBUTE = "__rdv_tangent"
POINTINESS_ATTRIBUTE = shaders_map.MESH_DERIVED_ATTRIBUTES["Pointiness"]
RANDOM_PER_ISLAND_ATTRIBUTE = shaders_map.MESH_DERIVED_ATTRIBUTES["Random Per Island"]


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


def _sum_by(index, values, n):
    """Rows of values summed by index into n rows (np.add.at, by bincount: many times faster)."""
    return np.stack([np.bincount(index, weights=values[:, c], minlength=n) for c in range(values.shape[1])], axis=1)


def pointiness(co, vertex_normals, edges):
    """Cycles' Pointiness per vertex (its Blender sync, attr_create_pointiness, written from
    the algorithm): vertices at the same position are welded (their normals summed); at each,
    the angle between the normal and the mean direction of its edges, over pi (0.5 on a flat
    surface, more at a ridge, less in a valley), then averaged with its edge neighbours' (a
    blur over the two-ring). co, vertex_normals: (n, 3); edges: (m, 2) vertex indices
    (Blender's edges, not the triangulation's). Cycles welds vertices closer than about 3e-4
    whose coordinate sums agree to 3 float epsilons; here positions equal bit for bit."""
    n = len(co)
    if n == 0:
        return np.zeros(0, np.float32)
    rows = np.ascontiguousarray(co, dtype=np.float32) + np.float32(0.0)  # -0 is 0, as Cycles compares
    _, first, inverse = np.unique(rows.view(np.dtype((np.void, 12))).reshape(-1), return_index=True,
                                  return_inverse=True)
    rep = first[inverse.reshape(-1)]  # each vertex's welded representative
    co = co.astype(np.float64)
    normal = _sum_by(rep, vertex_normals.astype(np.float64), n)
    length = np.linalg.norm(normal, axis=1, keepdims=True)
    normal = np.divide(normal, length, out=np.zeros_like(normal), where=length > 0)
    e = np.sort(rep[edges.reshape(-1, 2).astype(np.int64)], axis=1)
    key = np.unique(e[:, 0] * n + e[:, 1])
    e = np.stack([key // n, key % n], axis=1)
    d = co[e[:, 1]] - co[e[:, 0]]
    dl = np.linalg.norm(d, axis=1)
    e, d = e[dl > 0], d[dl > 0] / dl[dl > 0, None]  # an edge between welded vertices has no direction
    accum = _sum_by(e[:, 0], d, n) - _sum_by(e[:, 1], d, n)
    count = np.bincount(e.reshape(-1), minlength=n).astype(np.float64)
    mean = np.divide(accum, count[:, None], out=np.zeros_like(accum), where=count[:, None] > 0)
    raw = np.where(count > 0, np.arccos(np.clip((normal * mean).sum(axis=1), -1.0, 1.0)) / np.pi, 0.0)
    blurred = raw + np.bincount(e[:, 0], weights=raw[e[:, 1]], minlength=n) + \
        np.bincount(e[:, 1], weights=raw[e[:, 0]], minlength=n)
    blurred /= count + 1
    return blurred[rep].astype(np.float32)


def _hash_uint_to_float(k):
    """Cycles' hash_uint_to_float (Jenkins' lookup3 final mix of one word, then n / (2^32 - 1)
    in float), vectorised over uint32 k."""
    k = np.asarray(k, dtype=np.uint32)
    with np.errstate(over="ignore"):
        seed = np.uint32(0xDEADBEEF + (1 << 2) + 13)
        a, b, c = k + seed, np.full_like(k, seed), np.full_like(k, seed)

        def rot(x, r):
            return (x << np.uint32(r)) | (x >> np.uint32(32 - r))
        c ^= b; c -= rot(b, 14)  # noqa: E702
        a ^= c; a -= rot(c, 11)  # noqa: E702
        b ^= a; b -= rot(a, 25)  # noqa: E702
        c ^= b; c -= rot(b, 16)  # noqa: E702
        a ^= c; a -= rot(c, 4)  # noqa: E702
        b ^= a; b -= rot(a, 14)  # noqa: E702
        c ^= b; c -= rot(b, 24)  # noqa: E702
    return c.astype(np.float32) * np.float32(1.0 / np.float32(4294967295.0))


def random_per_island(num_vertices, edges):
    """Cycles' Random Per Island per vertex: the islands are the mesh's edge-connected vertex
    sets, joined edge by edge in Blender's order as Cycles' disjoint set joins them (union by
    rank, the first root kept on a tie), so each island's representative, and the hash of its
    index, is the vertex Cycles hashes. Every vertex of a face is in one island: the value is
    the face's."""
    parent = list(range(num_vertices))
    rank = [0] * num_vertices

    def find(x):
        root = x
        while parent[root] != root:
            root = parent[root]
        while parent[x] != root:
            parent[x], x = root, parent[x]
        return root
    for a, b in edges.reshape(-1, 2).tolist():
        ra, rb = find(a), find(b)
        if ra == rb:
            continue
        if rank[ra] < rank[rb]:
            ra, rb = rb, ra
        parent[rb] = ra
        if rank[ra] == rank[rb]:
            rank[ra] += 1
    roots = np.array([find(v) for v in range(num_vertices)], dtype=np.uint32)
    return _hash_uint_to_float(roots)


def geometry_attribute(me, name):
    """Pointiness or Random Per Island of an evaluated mesh, per Blender vertex (float32)."""
    nv, ne = len(me.vertices), len(me.edges)
    edges = _get(me.edges, "vertices", ne, np.uint32, 2).reshape(-1, 2)
    if name == POINTINESS_ATTRIBUTE:
        return pointiness(_get(me.vertices, "co", nv, np.float32, 3).reshape(-1, 3),
                          _vertex_normals(me, nv).reshape(-1, 3), edges)
    return random_per_island(nv, edges)


def _tangents(me, n_loops):
    """Per-corner (tangent x, y, z, bitangent sign) of the default UV map, from Blender's
    MikkTSpace (Mesh.calc_tangents), or None where Blender cannot make them (no UV map, faces
    of more than four corners): the engine then frames the map by the UVs' dp/du."""
    layer = _uv_layer(me, None)
    if layer is None:
        return None
    try:
        me.calc_tangents(uvmap=layer.name)
    except RuntimeError:
        return None
    t = _get(me.loops, "tangent", n_loops, np.float32, 3).reshape(-1, 3)
    sign = _get(me.loops, "bitangent_sign", n_loops, np.float32).reshape(-1, 1)
    return np.ascontiguousarray(np.hstack([t, sign]), dtype=np.float32).reshape(-1)


def _corner_attributes(me, names, n_loops, loop_vi, npoly):
    """Named UV maps / colour / generic attributes as per-corner float32 arrays."""
    out = []
    loop_poly = None
    for name in names:
        if name == TANGENT_ATTRIBUTE:
            tangents = _tangents(me, n_loops)
            if tangents is not None:
                out.append((name, "color", tangents, 4))
            continue
        if name in (POINTINESS_ATTRIBUTE, RANDOM_PER_ISLAND_ATTRIBUTE):
            data = np.repeat(geometry_attribute(me, name)[loop_vi].reshape(-1, 1), 3, axis=1)
            out.append((name, "color", np.ascontiguousarray(data, dtype=np.float32).reshape(-1), 3))
            continue
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
