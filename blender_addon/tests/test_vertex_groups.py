"""Vertex groups carried over to a result (docs/math.md#cage-corners): every group of the source
with the same name and order, the active one kept, each output vertex weighted by the UV rule
("keep corners") applied to per-vertex weights: the cage vertex's weight at its corner, the mean
of the edge's two weights at an edge midpoint, the mean of the face's weights at its centre.
Vertices of weight 0 are not in the group (as Subdivision Surface does)."""

import bpy
import numpy as np
import pytest

import helpers

STRUCTURES = ["DUAL", "TOPOLOGY"]
# The quad layout at r = 2 and the triangle layout at r = 4 (4 steps per side in both).
LAYOUTS = [("QUADS", 2), ("TRIANGLES", 4)]


def mod():
    return helpers.mesh_module()


def group_weights(obj, name):
    """(weights (V,), member mask (V,)) of group `name` of `obj` (a loop: test code only)."""
    index = obj.vertex_groups[name].index
    n = len(obj.data.vertices)
    w, member = np.zeros(n), np.zeros(n, dtype=bool)
    for v in obj.data.vertices:
        for e in v.groups:
            if e.group == index:
                w[v.index], member[v.index] = e.weight, True
    return w, member


def source_weights(obj, name):
    return group_weights(obj, name)[0]


def cube_with_groups():
    """The primitive cube with group "Top" (its 4 vertices with z > 0 at 1.0), group "Ramp"
    (vertex v at (v + 1) / 8, exact in binary) and "Empty" (no vertex); "Ramp" is active."""
    src = helpers.add_primitive("cube")
    co = np.empty(len(src.data.vertices) * 3, dtype=np.float32)
    src.data.vertices.foreach_get("co", co)
    top = np.flatnonzero(co.reshape(-1, 3)[:, 2] > 0)
    assert len(top) == 4
    src.vertex_groups.new(name="Top").add(top.tolist(), 1.0, 'REPLACE')
    ramp = src.vertex_groups.new(name="Ramp")
    for v in range(8):
        ramp.add([v], (v + 1) / 8, 'REPLACE')
    src.vertex_groups.new(name="Empty")
    src.vertex_groups.active_index = 1
    return src


def loop_points(conv, sizes, indices):
    """Per output face corner: (output vertex, cage face, corner, σ, τ) and the cage vertices
    a = the corner's, b = the next, p = the previous. The triangle layout's corners have their
    own cage corner (cage_loop_corner)."""
    k = conv.cage_coords.shape[0] // len(conv.cage_corner)
    corner = conv.cage_loop_corner if len(conv.cage_loop_corner) else np.repeat(conv.cage_corner, k, axis=0)
    f = corner[:, 0].astype(np.int64)
    c = corner[:, 1].astype(np.int64)
    starts = np.concatenate(([0], np.cumsum(sizes)[:-1])).astype(np.int64)
    n = sizes.astype(np.int64)[f]
    a = indices[starts[f] + c]
    b = indices[starts[f] + (c + 1) % n]
    verts = np.asarray(conv.faces, dtype=np.int64).reshape(-1)
    return verts, f, conv.cage_coords, a, b


def convert(src, method, layout=LAYOUTS[0]):
    opts = {"method": method, "resolution": layout[1], "face_layout": layout[0]}
    assert bpy.ops.object.gbsurf_convert(**opts) == {'FINISHED'}
    out = bpy.context.active_object
    lib_options, outputs = mod().core.split_options(opts)
    conv = mod().core.compute(src, lib_options, outputs)
    assert mod().core.VERTEX_GROUPS_SKIPPED not in conv.warnings
    assert len(conv.cage_coords) == len(out.data.loops)
    return out, conv


@pytest.mark.parametrize("method", STRUCTURES)
def test_groups_keep_names_order_and_active(method):
    src = cube_with_groups()
    out, _ = convert(src, method)
    assert [g.name for g in out.vertex_groups] == ["Top", "Ramp", "Empty"]
    assert out.vertex_groups.active.name == "Ramp"
    assert not group_weights(out, "Empty")[1].any()


@pytest.mark.parametrize("layout", LAYOUTS)
@pytest.mark.parametrize("method", STRUCTURES)
def test_top_group_weights(method, layout):
    src = cube_with_groups()
    out, conv = convert(src, method, layout)
    w, member = group_weights(out, "Top")
    assert ((w >= 0) & (w <= 1)).all()
    assert (member == (w > 0)).all()  # weight 0 = not in the group
    positions, sizes, indices = mod().mesh_io.read_mesh(src.data)
    verts, f, st, a, b = loop_points(conv, sizes, indices.astype(np.int64))
    top = positions[:, 2] > 0
    # Cage vertex samples (σ, τ) = (0, 0): 1 at the top corners, 0 (not in the group) below.
    at = (st == 0).all(axis=1)
    # 6 faces x 4 corners; triangles: 2 triangles at a patch corner (topology), 3 at the patch
    # centre of a valence-3 vertex (dual).
    assert at.sum() == {"QUADS": 24, "TRIANGLES": 48 if method == "TOPOLOGY" else 24}[layout[0]]
    assert len(set(zip(f[at].tolist(), a[at].tolist()))) == 24
    assert (w[verts[at]] == top[a[at]]).all()
    assert len(set(verts[at][member[verts[at]]].tolist())) == len(set(verts[at][top[a[at]]].tolist())) == 4
    # Edge midpoints (1, 0): 0.5 on the 4 vertical edges, 1 on the top square, 0 on the bottom.
    at = (st == [1, 0]).all(axis=1)
    expect = 0.5 * (top[a[at]].astype(float) + top[b[at]])
    assert (w[verts[at]] == expect).all()
    assert len(set(verts[at][expect == 0.5].tolist())) == 4
    # Face centres (1, 1): 1 on the top face, 0.5 on the sides, 0 on the bottom.
    at = (st == 1).all(axis=1)
    centre = {f_: np.mean(top[indices[4 * f_:4 * f_ + 4]]) for f_ in range(6)}
    assert sorted(centre.values()) == [0, 0.5, 0.5, 0.5, 0.5, 1]
    assert (w[verts[at]] == [centre[x] for x in f[at]]).all()
    # Near the top corners (their sectors) at least 0.5, near the bottom ones at most 0.5, 1 on
    # the whole top face.
    near_top = top[a]
    assert (w[verts[near_top]] >= 0.5).all() and (w[verts[~near_top]] <= 0.5).all()
    top_face = [x for x in range(6) if centre[x] == 1]
    assert (w[verts[f == top_face[0]]] == 1).all()
    # Continuous: every face corner of a vertex gives the vertex's weight (the per-loop rule).
    per_loop = mod().mesh_io.cage_loop_values(
        top[indices].astype(float)[:, None], sizes, conv.cage_corner, conv.cage_coords,
        conv.cage_loop_corner)[:, 0]
    assert np.allclose(per_loop, w[verts], atol=1e-7)


@pytest.mark.parametrize("layout", LAYOUTS)
@pytest.mark.parametrize("method", STRUCTURES)
def test_varying_weights_are_exact_at_the_cage_samples(method, layout):
    # Dual: (σ, τ) = (0, 0) is the patch centre of the cage vertex's patch; topology: the patch
    # corner at the cage vertex. Either way the output vertex there has the vertex's own weight
    # (v + 1) / 8, the edge midpoint the mean of two, the face centre the mean of four: all
    # multiples of 1/64, exact in float32.
    src = cube_with_groups()
    out, conv = convert(src, method, layout)
    w, member = group_weights(out, "Ramp")
    ramp = source_weights(src, "Ramp")
    assert ramp.tolist() == [(v + 1) / 8 for v in range(8)]
    _, sizes, indices = mod().mesh_io.read_mesh(src.data)
    indices = indices.astype(np.int64)
    verts, f, st, a, b = loop_points(conv, sizes, indices)
    at = (st == 0).all(axis=1)
    # One output vertex per cage vertex.
    assert len(set(verts[at].tolist())) == len(set(zip(verts[at].tolist(), a[at].tolist()))) == 8
    assert (w[verts[at]] == ramp[a[at]]).all()
    at = (st == [1, 0]).all(axis=1)
    assert (w[verts[at]] == (ramp[a[at]] + ramp[b[at]]) / 2).all()
    at = (st == 1).all(axis=1)
    assert (w[verts[at]] == ramp[indices].reshape(6, 4).mean(axis=1)[f[at]]).all()
    assert member.all() and (w >= 1 / 8).all() and (w <= 1).all()
    per_loop = mod().mesh_io.cage_loop_values(ramp[indices][:, None], sizes, conv.cage_corner,
                                              conv.cage_coords, conv.cage_loop_corner)[:, 0]
    assert np.allclose(per_loop, w[verts], atol=1e-6)


def test_source_without_groups_gives_none():
    helpers.add_primitive("cube")
    assert bpy.ops.object.gbsurf_convert(method='TOPOLOGY', resolution=2) == {'FINISHED'}
    assert len(bpy.context.active_object.vertex_groups) == 0


@pytest.mark.parametrize("method", ["CATMULL_CLARK", "DOO_SABIN"])
def test_subdivision_skips_groups_with_a_message(method):
    src = cube_with_groups()
    lib_options, outputs = mod().core.split_options({"method": method, "levels": 2})
    conv = mod().core.compute(src, lib_options, outputs)
    assert mod().core.VERTEX_GROUPS_SKIPPED in conv.warnings
    out = mod().core.build_result(src, conv, lib_options, outputs)
    assert len(out.vertex_groups) == 0
    # A source without groups gets no such message.
    plain = helpers.add_primitive("cube")
    conv = mod().core.compute(plain, lib_options, outputs)
    assert mod().core.VERTEX_GROUPS_SKIPPED not in conv.warnings


@pytest.mark.parametrize("layout", LAYOUTS)
def test_update_and_live_mode_carry_new_weights(layout):
    src = cube_with_groups()
    out, _ = convert(src, "TOPOLOGY", layout)
    src.vertex_groups["Top"].add(list(range(8)), 0.25, 'REPLACE')
    src.data.update()
    helpers.select_only(out)
    assert bpy.ops.object.gbsurf_update() == {'FINISHED'}
    assert [g.name for g in out.vertex_groups] == ["Top", "Ramp", "Empty"]
    w, member = group_weights(out, "Top")
    assert member.all() and np.allclose(w, 0.25)
    out.gbsurf.live = True
    bpy.context.view_layer.update()
    src.vertex_groups["Top"].add(list(range(8)), 0.75, 'REPLACE')
    src.data.update()
    bpy.context.view_layer.update()
    w, member = group_weights(out, "Top")
    assert member.all() and np.allclose(w, 0.75)
    assert out.vertex_groups.active.name == "Ramp"


def test_armature_deforms_the_result_by_the_carried_group():
    src = cube_with_groups()
    out, _ = convert(src, "DUAL")
    arm_data = bpy.data.armatures.new("Rig")
    rig = bpy.data.objects.new("Rig", arm_data)
    bpy.context.scene.collection.objects.link(rig)
    helpers.select_only(rig)
    bpy.ops.object.mode_set(mode='EDIT')
    bone = arm_data.edit_bones.new("Top")
    bone.head, bone.tail = (0, 0, 0), (0, 0, 1)
    bpy.ops.object.mode_set(mode='OBJECT')
    out.matrix_world = rig.matrix_world.copy()
    m = out.modifiers.new("Armature", 'ARMATURE')
    m.object = rig
    assert m.use_vertex_groups
    rig.pose.bones["Top"].location = (0, 1, 0)  # bone y = world z: up by 1
    dg = bpy.context.evaluated_depsgraph_get()
    ev = out.evaluated_get(dg)
    moved = np.empty(len(out.data.vertices) * 3, dtype=np.float32)
    ev.data.vertices.foreach_get("co", moved)
    rest = np.empty_like(moved)
    out.data.vertices.foreach_get("co", rest)
    dz = (moved - rest).reshape(-1, 3)
    _, member = group_weights(out, "Top")
    # One bone: the armature normalises over the vertex's groups it deforms with, so every
    # member moves by the full 1 and the others stay.
    assert member.any() and (~member).any()
    assert np.allclose(dz[member], [0, 0, 1], atol=1e-5)
    assert np.allclose(dz[~member], 0, atol=1e-6)


def test_group_named_like_an_attribute():
    # "UVMap" and "gb_patch" are attribute names on the result: those groups take the other
    # path (VertexGroup.add per distinct weight) and come out the same.
    src = cube_with_groups()
    for name in ("UVMap", "gb_patch"):
        g = src.vertex_groups.new(name=name)
        for v in range(8):
            g.add([v], (v + 1) / 8, 'REPLACE')
    out, _ = convert(src, "TOPOLOGY")
    names = [g.name for g in out.vertex_groups]
    assert names == ["Top", "Ramp", "Empty", "UVMap", "gb_patch"]
    ramp = group_weights(out, "Ramp")[0]
    assert (group_weights(out, "UVMap")[0] == ramp).all()
    assert (group_weights(out, "gb_patch")[0] == ramp).all()
    assert "gb_patch" in out.data.attributes and "UVMap" in out.data.uv_layers
