"""Mesh data in and out of Blender with numpy (`foreach_get`/`foreach_set`, no per-vertex loops).

Input keeps n-gons: faces are read as polygon `loop_start`/`loop_total` plus the corners' vertex
indices (loop triangles are never used). Output builds the mesh by
`vertices.add`/`loops.add`/`polygons.add` and `foreach_set`. Positions and corner vertices go
through the generic attributes `position` and `.corner_vert` when the mesh has them (Blender 4+):
their `foreach_set` copies the buffer at once, while `loops.foreach_set("vertex_index")` is about
300 times slower (0.3 s for 1.9 M corners).
"""

import bpy
import numpy as np

from . import native


def _set_corner_verts(mesh, idx):
    """Corner vertex indices: the `.corner_vert` attribute (Blender 4+) is ~100x faster than
    `loops.foreach_set("vertex_index")`, which goes through RNA per element."""
    attr = mesh.attributes.get(".corner_vert")
    if attr is not None:
        attr.data.foreach_set("value", idx)
    else:
        mesh.loops.foreach_set("vertex_index", idx)


def _get_corner_verts(mesh, out):
    attr = mesh.attributes.get(".corner_vert")
    if attr is not None and len(attr.data) == len(out):
        attr.data.foreach_get("value", out)
    else:
        mesh.loops.foreach_get("vertex_index", out)


def _set_positions(mesh, co):
    attr = mesh.attributes.get("position")
    if attr is not None and attr.data_type == 'FLOAT_VECTOR':
        attr.data.foreach_set("vector", co)
    else:
        mesh.vertices.foreach_set("co", co)


def _get_positions(mesh, out):
    attr = mesh.attributes.get("position")
    if attr is not None and attr.data_type == 'FLOAT_VECTOR' and len(attr.data) * 3 == len(out):
        attr.data.foreach_get("vector", out)
    else:
        mesh.vertices.foreach_get("co", out)


class SourceError(ValueError):
    """The source mesh cannot be converted (names the element)."""


class MeshData(tuple):
    """(positions, face_sizes, face_indices) as read by `read_mesh`, plus `creases`: None or
    (edge_vertices (E,2) uint32, edge_sharpness (E,) float64, vertices (K,) uint32,
    vertex_sharpness (K,) float64) from `read_creases`."""

    creases = None


def _float_attribute(mesh, name, domain, n):
    """The float attribute `name` on `domain` with `n` values (numpy), or None."""
    attr = mesh.attributes.get(name)
    if attr is None or attr.domain != domain or attr.data_type != 'FLOAT' or len(attr.data) != n:
        return None
    out = np.empty(n, dtype=np.float32)
    attr.data.foreach_get("value", out)
    return out.astype(np.float64)


def read_creases(mesh):
    """Blender's crease attributes as the library's sharpness: `crease_edge` (edge domain) and
    `crease_vert` (point domain). The Subdivision Surface modifier reads a crease c as
    OpenSubdiv sharpness 10·c², and the library's sharpness is that same c (docs/math.md#creases),
    so the values pass through unchanged; only entries above 0 are kept. None when there is no
    crease."""
    ne, nv = len(mesh.edges), len(mesh.vertices)
    ec = _float_attribute(mesh, "crease_edge", 'EDGE', ne)
    vc = _float_attribute(mesh, "crease_vert", 'POINT', nv)
    ev = np.empty((0, 2), dtype=np.uint32)
    es = np.empty(0, dtype=np.float64)
    if ec is not None and ne and np.any(ec > 0):
        verts = np.empty(ne * 2, dtype=np.int32)
        mesh.edges.foreach_get("vertices", verts)
        keep = ec > 0
        ev = verts.reshape(-1, 2)[keep].astype(np.uint32)
        es = np.clip(ec[keep], 0.0, 1.0)
    vv = np.empty(0, dtype=np.uint32)
    vs = np.empty(0, dtype=np.float64)
    if vc is not None and nv and np.any(vc > 0):
        keep = vc > 0
        vv = np.nonzero(keep)[0].astype(np.uint32)
        vs = np.clip(vc[keep], 0.0, 1.0)
    if len(es) == 0 and len(vs) == 0:
        return None
    return ev, es, vv, vs


F32_MAX = float(np.finfo(np.float32).max)


class Float32RangeError(ValueError):
    """An output position beyond Blender's float32 coordinates (names the vertex): the library
    accepts coordinates up to 1e150, Blender stores float32, which would make it inf."""


def float32_positions(positions):
    """(V, 3) float32 copy of `positions`; a coordinate with |x| > float32 max raises
    Float32RangeError naming the first such vertex (never a silent inf)."""
    p = np.asarray(positions, dtype=np.float64).reshape(-1, 3)
    bad = np.flatnonzero((np.abs(p) > F32_MAX).any(axis=1))
    if len(bad):
        i = int(bad[0])
        x = p[i][int(np.argmax(np.abs(p[i])))]
        raise Float32RangeError(
            f"vertex {i}: coordinate {x:g} is beyond Blender's float32 range (|x| <= {F32_MAX:g})")
    return np.ascontiguousarray(p, dtype=np.float32)


def float32_clamped(values):
    """float32 copy of per-vertex display values (curvatures): values beyond the float32 range
    become +-float32 max, never inf (the same rule as the library's PLY `float` fields; the
    exact float64 values stay available from the library)."""
    v = np.asarray(values, dtype=np.float64).reshape(-1)
    return np.ascontiguousarray(np.clip(v, -F32_MAX, F32_MAX), dtype=np.float32)


def read_mesh(mesh, group_names=(), group_active=-1):
    """(positions (V,3) float64, face_sizes (F,) uint32, face_indices (sum sizes,) uint32) as a
    `MeshData` whose `creases` are `read_creases(mesh)`, `faces` `read_face_data(mesh)` and
    `vertex_groups` `read_vertex_groups(mesh, group_names, group_active)` (None without
    names: a Mesh alone does not expose its groups' names to Python, its object does)."""
    nv, nl, nf = len(mesh.vertices), len(mesh.loops), len(mesh.polygons)
    co = np.empty(nv * 3, dtype=np.float32)
    _get_positions(mesh, co)
    sizes = np.empty(nf, dtype=np.int32)
    mesh.polygons.foreach_get("loop_total", sizes)
    starts = np.empty(nf, dtype=np.int32)
    mesh.polygons.foreach_get("loop_start", starts)
    corner_verts = np.empty(nl, dtype=np.int32)
    _get_corner_verts(mesh, corner_verts)
    # Blender stores the corners of face f at loop_start[f] .. + loop_total[f]; faces are in
    # order in every mesh Blender builds, but gather explicitly if not.
    expected = np.concatenate(([0], np.cumsum(sizes)[:-1])) if nf else starts
    if nf and not np.array_equal(starts, expected):
        order = np.repeat(starts, sizes) + (np.arange(sizes.sum()) - np.repeat(expected, sizes))
        corner_verts = corner_verts[order]
    else:
        corner_verts = corner_verts[: int(sizes.sum())]
    data = MeshData((
        co.astype(np.float64).reshape(-1, 3),
        sizes.astype(np.uint32),
        corner_verts.astype(np.uint32),
    ))
    data.creases = read_creases(mesh)
    data.faces = read_face_data(mesh, None if nf == 0 or np.array_equal(starts, expected) else order, int(sizes.sum()))
    data.vertex_groups = read_vertex_groups(mesh, group_names, group_active)
    return data


class VertexGroups:
    """A source's vertex groups (see `carry_vertex_groups`): names in order, active (index into
    names, -1 for none), weights (len(names), V) float32 with 0 for a vertex not in the group."""

    def __init__(self, names, active, weights):
        self.names = list(names)
        self.active = active
        self.weights = weights


def read_vertex_groups(mesh, names, active=-1):
    """The weights of the vertex groups `names` (the object's `vertex_groups`, in order) of
    `mesh` as `VertexGroups`, None when there are no names. bpy has no bulk reader of deform
    weights (they are not generic attributes and `foreach_get` does not reach them), so this is
    the one pass over the source's vertices' group entries; the result side is numpy-only."""
    names = list(names)
    if not names:
        return None
    nv = len(mesh.vertices)
    weights = np.zeros((len(names), nv), dtype=np.float32)
    entries = [(e.group, v.index, e.weight) for v in mesh.vertices for e in v.groups]
    if entries:
        e = np.array(entries, dtype=np.float64)
        g, i = e[:, 0].astype(np.int64), e[:, 1].astype(np.int64)
        ok = (g >= 0) & (g < len(names))
        weights[g[ok], i[ok]] = np.clip(e[ok, 2], 0.0, 1.0)
    return VertexGroups(names, active if 0 <= active < len(names) else -1, weights)


class FaceData:
    """What a result carries over from its cage per face and face corner (see `carry_cage_data`):
    material_index (F,) int32, uv_maps: {name: (sum sizes, 2) float32 in face-corner order},
    uv_active: the active UV map's name or None."""

    def __init__(self, material_index, uv_maps, uv_active):
        self.material_index = material_index
        self.uv_maps = uv_maps
        self.uv_active = uv_active


def read_face_data(mesh, order, n_corners):
    """The per-face material indices and every UV map of `mesh` (corners gathered by `order`
    like the corner vertices, None when in order), numpy only."""
    nf = len(mesh.polygons)
    mi = np.zeros(nf, dtype=np.int32)
    if nf:
        mesh.polygons.foreach_get("material_index", mi)
    uv_maps = {}
    nl = len(mesh.loops)
    for layer in mesh.uv_layers:
        uv = np.empty(nl * 2, dtype=np.float32)
        if hasattr(layer, "uv"):
            layer.uv.foreach_get("vector", uv)
        else:
            layer.data.foreach_get("uv", uv)
        uv = uv.reshape(-1, 2)
        uv_maps[layer.name] = uv[order] if order is not None else uv[:n_corners]
    active = mesh.uv_layers.active
    return FaceData(mi, uv_maps, active.name if active is not None else None)


def _loop_corners(cage_corner, st, loop_corner):
    """Per loop (face corner of the output) its cage corner (N,2) int64: `loop_corner` (N,2)
    when given (the triangle layout: each corner's own), else its face's `cage_corner` (F,2)
    repeated for the m = N/F corners of every face. None when the sizes do not fit."""
    loop_corner = np.asarray(loop_corner if loop_corner is not None else (), dtype=np.int64).reshape(-1, 2)
    if len(loop_corner):
        return loop_corner if len(loop_corner) == len(st) else None
    cage_corner = np.asarray(cage_corner, dtype=np.int64).reshape(-1, 2)
    nq = len(cage_corner)
    if nq == 0 or len(st) % nq:
        return None
    return np.repeat(cage_corner, len(st) // nq, axis=0)


def cage_loop_values(values, face_sizes, cage_corner, cage_coords, loop_corner=None):
    """Per output face corner, a cage attribute given per cage face corner (`values` (sum sizes,
    k) in face-corner order) interpolated like Subdivision Surface's "keep corners"
    (docs/math.md#cage-corners): bilinear between the corner's value, the two adjacent edge
    midpoints' values and the face centre's (the mean over the face's corners), at the loop's
    cage coordinates. `cage_corner` (F,2), `cage_coords` (m·F,2), m corners per output face;
    `loop_corner` (m·F,2) the triangle layout's per-corner cage corners (used in place of the
    face's when not empty). Faces with an unknown cage corner get 0; a corner outside the cage or
    arrays that do not fit raise `native.GbsurfError`. Computed by the library
    (`native.cage_loop_values`), float32."""
    return native.cage_loop_values(face_sizes, values, cage_corner, loop_corner, cage_coords)


def cage_vertex_values(values, face_sizes, face_indices, cage_corner, cage_coords, faces, n_vertices,
                       loop_corner=None):
    """Per output vertex, a cage attribute given per cage vertex (`values` (V_cage, k)), by the
    keep-corners rule of `cage_loop_values` with per-vertex data: the corner's vertex value, at
    the edge midpoints the mean of the edge's two vertices, at the centre the mean of the face's
    vertices. Each output vertex is evaluated at one of its face corners (the rule is continuous:
    every corner gives the same value, up to rounding). `faces` (F, m) output faces, `n_vertices` their vertex
    count, `loop_corner` as in `cage_loop_values`; vertices of no face, or of a face with no cage
    coordinates, get 0. The values come from the library (`native.cage_loop_values` at one loop
    per vertex)."""
    values = np.asarray(values, dtype=np.float64)
    sizes = np.asarray(face_sizes, dtype=np.int64)
    st = np.asarray(cage_coords, dtype=np.float64).reshape(-1, 2)
    verts = np.asarray(faces, dtype=np.int64).reshape(-1)
    out = np.zeros((n_vertices, values.shape[1]), dtype=np.float64)
    corners = _loop_corners(cage_corner, st, loop_corner)
    if len(sizes) == 0 or corners is None or len(st) != len(verts):
        return out
    ok = (verts >= 0) & (verts < n_vertices)
    loop = np.full(n_vertices, -1, dtype=np.int64)
    loop[verts[ok]] = np.flatnonzero(ok)  # one face corner per vertex (which one does not matter)
    has = np.flatnonzero(loop >= 0)
    lp = loop[has]
    corner_values = values[np.asarray(face_indices, dtype=np.int64)]
    out[has] = native.cage_loop_values(sizes, corner_values, (), corners[lp], st[lp])
    return out


def carry_cage_data(mesh, cage_corner, cage_coords, face_sizes, faces, loop_corner=None):
    """Carries a cage's `faces` (FaceData) over to a result mesh built from the conversion's
    faces: each face's material index is its cage face's; every UV map is interpolated per face
    corner with `cage_loop_values` (`loop_corner`: the triangle layout's per-corner cage corners;
    the subdivision methods give no coordinates, so no UVs)."""
    if faces is None:
        return
    cage_corner = np.asarray(cage_corner, dtype=np.int64).reshape(-1, 2)
    if len(cage_corner) == len(mesh.polygons) and len(faces.material_index):
        f = cage_corner[:, 0]
        valid = f < len(faces.material_index)
        set_face_materials(mesh, np.where(valid, faces.material_index[np.where(valid, f, 0)], 0))
    if len(cage_coords) != len(mesh.loops) or len(cage_coords) == 0:
        return
    for name, uv in faces.uv_maps.items():
        layer = mesh.uv_layers.new(name=name)
        if layer is None:  # Blender's limit on UV maps
            break
        vals = cage_loop_values(uv, face_sizes, cage_corner, cage_coords, loop_corner)
        vals = np.ascontiguousarray(vals, dtype=np.float32).reshape(-1)  # no copy: already float32
        if hasattr(layer, "uv"):
            layer.uv.foreach_set("vector", vals)
        else:
            layer.data.foreach_set("uv", vals)
    if faces.uv_active is not None and faces.uv_active in mesh.uv_layers:
        mesh.uv_layers.active = mesh.uv_layers[faces.uv_active]
        mesh.uv_layers[faces.uv_active].active_render = True


GROUP_CHUNK = 16  # vertex groups interpolated at once (bounds the temporary arrays)


def carry_vertex_groups(mesh, groups, face_sizes, face_indices, cage_corner, cage_coords, faces,
                        loop_corner=None):
    """Gives a result mesh its cage's vertex groups (`VertexGroups`): the same names in the same
    order, the same active group, each output vertex weighted by `cage_vertex_values` (the UV
    rule with per-vertex weights, docs/math.md#cage-corners); a weight of 0 leaves the vertex out
    of the group, as Subdivision Surface does. `loop_corner`: the triangle layout's per-corner
    cage corners. Returns False (nothing added) without cage coordinates (subdivision methods),
    else True.

    Vertex group names belong to the mesh (an object only shows its mesh's), so the groups are
    made through a temporary object that is removed again. Each group's weights go in as a float
    point attribute (`foreach_set`) turned into a group by `geometry.attribute_convert`, which
    skips zeros: 0.16 s for 160k vertices of all-distinct weights, where `VertexGroup.add` per
    distinct weight takes 1.9 s. Where that operator cannot run (or the name is taken by an
    attribute), `VertexGroup.add` per distinct weight does it."""
    if groups is None or not groups.names:
        return True
    faces = np.asarray(faces)
    if len(cage_coords) == 0 or len(cage_coords) != faces.size:
        return False
    nv = len(mesh.vertices)
    tmp = bpy.data.objects.new("gbsurf vertex groups", mesh)
    try:
        for lo in range(0, len(groups.names), GROUP_CHUNK):
            hi = min(lo + GROUP_CHUNK, len(groups.names))
            w = cage_vertex_values(groups.weights[lo:hi].T, face_sizes, face_indices, cage_corner,
                                   cage_coords, faces, nv, loop_corner)
            w = np.clip(w, 0.0, 1.0).astype(np.float32)
            for j, name in enumerate(groups.names[lo:hi]):
                _add_vertex_group(tmp, name, np.ascontiguousarray(w[:, j]))
        if groups.active >= 0:
            tmp.vertex_groups.active_index = groups.active
    finally:
        bpy.data.objects.remove(tmp, do_unlink=True)
    return True


def _add_vertex_group(obj, name, weights):
    """Appends vertex group `name` with per-vertex `weights` (float32, 0 = not in the group)."""
    mesh = obj.data
    if mesh.attributes.get(name) is None:
        attr = mesh.attributes.new(name, 'FLOAT', 'POINT')
        if attr.name == name:
            attr.data.foreach_set("value", weights)
            mesh.attributes.active = attr
            try:
                with bpy.context.temp_override(object=obj, active_object=obj):
                    done = bpy.ops.geometry.attribute_convert(mode='VERTEX_GROUP') == {'FINISHED'}
            except RuntimeError:
                done = False
            if done and obj.vertex_groups.get(name) is not None:
                return
        if mesh.attributes.get(attr.name) is not None:
            mesh.attributes.remove(mesh.attributes[attr.name])
    group = obj.vertex_groups.new(name=name)
    vals, inv = np.unique(weights, return_inverse=True)
    order = np.argsort(inv, kind='stable')
    cuts = np.searchsorted(inv[order], np.arange(len(vals) + 1))
    for k, v in enumerate(vals.tolist()):
        if v > 0:
            group.add(order[cuts[k]:cuts[k + 1]].tolist(), v, 'REPLACE')


def read_object(obj, depsgraph=None, vertex_groups=True):
    """The evaluated mesh (modifiers applied) of a mesh object, in its local coordinates, with
    its vertex groups' weights unless `vertex_groups` is False (a digest check needs none)."""
    if obj is None or obj.type != 'MESH':
        raise SourceError(f"{getattr(obj, 'name', None)!r} is not a mesh object")
    if depsgraph is None:
        depsgraph = bpy.context.evaluated_depsgraph_get()
    ev = obj.evaluated_get(depsgraph)
    mesh = ev.to_mesh()
    groups = ev.vertex_groups if vertex_groups else ()
    try:
        return read_mesh(mesh, [g.name for g in groups], groups.active_index if groups else -1)
    finally:
        ev.to_mesh_clear()


def write_triangles(mesh, positions, triangles, edges=None, corner_edges=None):
    """Fills an empty mesh with vertices and faces of one size (numpy path): triangles (T,3) or
    the quads (Q,4) of the quad layout, as the array's width says (a flat array is triangles).
    With the library's edge table (`edges` (E,2), `corner_edges` one per face corner: see
    `native.Conversion`) the edges are set directly; otherwise Blender derives them
    (`update(calc_edges=True)`: 0.6-1.2 s for 640k quads, against 0.01 s for the two
    attributes). Positions beyond float32 raise Float32RangeError (see float32_positions) before
    the mesh is touched."""
    positions = float32_positions(positions)
    faces = np.asarray(triangles)
    k = faces.shape[1] if faces.ndim == 2 and faces.shape[1] in (3, 4) else 3
    tris = np.ascontiguousarray(faces, dtype=np.int32).reshape(-1, k)
    nv, nt = len(positions), len(tris)
    mesh.vertices.add(nv)
    _set_positions(mesh, positions.reshape(-1))
    mesh.loops.add(nt * k)
    _set_corner_verts(mesh, tris.reshape(-1))
    mesh.polygons.add(nt)
    mesh.polygons.foreach_set("loop_start", np.arange(0, nt * k, k, dtype=np.int32))
    if edges is not None and corner_edges is not None and len(corner_edges) == nt * k and (nt == 0 or len(edges)):
        e = np.ascontiguousarray(edges, dtype=np.int32).reshape(-1)
        mesh.edges.add(len(e) // 2)
        _set_int_attribute(mesh, ".edge_verts", e, lambda: mesh.edges.foreach_set("vertices", e))
        ce = np.ascontiguousarray(corner_edges, dtype=np.int32).reshape(-1)
        _set_int_attribute(mesh, ".corner_edge", ce, lambda: mesh.loops.foreach_set("edge_index", ce))
        mesh.update()
    else:
        mesh.update(calc_edges=True)
    return mesh


def _set_int_attribute(mesh, name, values, fallback):
    """Sets an internal integer attribute (`.edge_verts`, `.corner_edge`) in one call, or through
    the slower RNA path `fallback` when this Blender does not expose it."""
    attr = mesh.attributes.get(name)
    if attr is not None:
        attr.data.foreach_set("value", values)
    else:
        fallback()


def set_face_materials(mesh, material_index):
    """Per-face material index (numpy, one value per polygon), e.g. the cage face's material
    carried to every output face descending from it. Written through the generic face attribute
    `material_index` (640k faces: 0.001 s, where `polygons.foreach_set` takes 0.19 s); a mesh
    without that attribute has index 0 everywhere, so all-zero indices add nothing."""
    idx = np.ascontiguousarray(material_index, dtype=np.int32).reshape(-1)
    attr = mesh.attributes.get("material_index")
    if attr is None:
        if not idx.any():
            return
        attr = mesh.attributes.new("material_index", 'INT', 'FACE')
    attr.data.foreach_set("value", idx)


def write_polygons(mesh, positions, face_sizes, face_indices, edges=None):
    """Fills an empty mesh with n-gons (and optional loose edges), numpy path. Positions beyond
    float32 raise Float32RangeError (see float32_positions) before the mesh is touched."""
    positions = float32_positions(positions)
    sizes = np.ascontiguousarray(face_sizes, dtype=np.int32).reshape(-1)
    idx = np.ascontiguousarray(face_indices, dtype=np.int32).reshape(-1)
    mesh.vertices.add(len(positions))
    _set_positions(mesh, positions.reshape(-1))
    if edges is not None and len(edges):
        e = np.ascontiguousarray(edges, dtype=np.int32).reshape(-1, 2)
        mesh.edges.add(len(e))
        mesh.edges.foreach_set("vertices", e.reshape(-1))
    mesh.loops.add(len(idx))
    _set_corner_verts(mesh, idx)
    mesh.polygons.add(len(sizes))
    starts = np.zeros(len(sizes), dtype=np.int32)
    if len(sizes) > 1:
        np.cumsum(sizes[:-1], out=starts[1:])
    mesh.polygons.foreach_set("loop_start", starts)
    mesh.update(calc_edges=True)
    return mesh


def set_point_attribute(mesh, name, kind, values):
    """Creates (or replaces) a per-vertex attribute: kind 'INT', 'FLOAT' or 'FLOAT_COLOR'.
    FLOAT values beyond float32 are clamped (float32_clamped), never inf."""
    old = mesh.attributes.get(name)
    if old is not None:
        mesh.attributes.remove(old)
    attr = mesh.attributes.new(name, kind, 'POINT')
    if kind == 'INT':
        attr.data.foreach_set("value", np.ascontiguousarray(values, dtype=np.int32).reshape(-1))
    elif kind == 'FLOAT':
        attr.data.foreach_set("value", float32_clamped(values))
    else:
        attr.data.foreach_set("color", np.ascontiguousarray(values, dtype=np.float32).reshape(-1))
    return attr


def get_point_attribute(mesh, name):
    """The values of a per-vertex attribute as numpy (INT, FLOAT or color attributes)."""
    attr = mesh.attributes[name]
    n = len(attr.data)
    if attr.data_type == 'INT':
        out = np.empty(n, dtype=np.int32)
        attr.data.foreach_get("value", out)
    elif attr.data_type == 'FLOAT':
        out = np.empty(n, dtype=np.float32)
        attr.data.foreach_get("value", out)
    else:
        out = np.empty(n * 4, dtype=np.float32)
        attr.data.foreach_get("color", out)
        out = out.reshape(-1, 4)
    return out


def shade_smooth(mesh):
    """Smooth shading of every face (`sharp_face` false)."""
    if hasattr(mesh, "shade_smooth"):
        mesh.shade_smooth()
    else:  # Blender < 4.1
        mesh.polygons.foreach_set("use_smooth", np.ones(len(mesh.polygons), dtype=bool))


# --- colour maps -------------------------------------------------------------------------------

def diverging_colors(values, scale=None):
    """Blue (negative) - white (zero) - red (positive) RGBA, |v| >= scale saturates.

    scale defaults to the 95th percentile of |values| (robust against spikes at corners)."""
    v = np.asarray(values, dtype=np.float64)
    if scale is None:
        finite = np.abs(v[np.isfinite(v)])
        scale = float(np.percentile(finite, 95)) if finite.size else 1.0
    if not scale > 0.0:
        scale = 1.0
    t = np.clip(np.nan_to_num(v / scale), -1.0, 1.0)
    rgba = np.ones((len(v), 4), dtype=np.float32)
    pos, neg = t > 0, t < 0
    rgba[pos, 1] = 1.0 - t[pos]
    rgba[pos, 2] = 1.0 - t[pos]
    rgba[neg, 0] = 1.0 + t[neg]
    rgba[neg, 1] = 1.0 + t[neg]
    return rgba


def sequential_colors(values, vmax=None):
    """Green (0) - yellow - red (>= vmax) RGBA; vmax defaults to max(values) (at least 1e-9)."""
    v = np.nan_to_num(np.asarray(values, dtype=np.float64))
    if vmax is None:
        vmax = float(v.max()) if v.size else 1.0
    vmax = max(vmax, 1e-9)
    t = np.clip(v / vmax, 0.0, 1.0)
    rgba = np.ones((len(v), 4), dtype=np.float32)
    rgba[:, 0] = np.clip(2.0 * t, 0.0, 1.0)
    rgba[:, 1] = np.clip(2.0 * (1.0 - t), 0.0, 1.0)
    rgba[:, 2] = 0.0
    return rgba


def index_colors(indices):
    """A distinct pastel colour per integer (hashing, deterministic)."""
    i = np.asarray(indices, dtype=np.uint64)
    h = (i * np.uint64(2654435761)) % np.uint64(2**32)
    rgba = np.ones((len(i), 4), dtype=np.float32)
    rgba[:, 0] = 0.35 + 0.6 * ((h & np.uint64(0xFF)) / 255.0)
    rgba[:, 1] = 0.35 + 0.6 * (((h >> np.uint64(8)) & np.uint64(0xFF)) / 255.0)
    rgba[:, 2] = 0.35 + 0.6 * (((h >> np.uint64(16)) & np.uint64(0xFF)) / 255.0)
    return rgba
