"""Cage data carried over to a result (docs/math.md#cage-corners): the material index of every
output face is its cage face's, the source's materials are linked, and every UV map is
interpolated like Subdivision Surface's "keep corners": equal to the source's UV at the cage
corners, the mean of the face's UVs at its centre, continuous within every cage face."""

import bpy
import numpy as np
import pytest

import helpers

STRUCTURES = ["DUAL", "TOPOLOGY"]


def mod():
    return helpers.mesh_module()


def cube_with_materials_and_checker():
    """The primitive cube with materials A (faces 0-2) and B (3-5) and a checker UV map: corner
    k of face f at the unit square's corner k, shifted by (f, parity of f)."""
    src = helpers.add_primitive("cube")
    mesh = src.data
    for name in ("A", "B"):
        mesh.materials.append(bpy.data.materials.new(name))
    mesh.polygons.foreach_set("material_index", np.array([0, 0, 0, 1, 1, 1], dtype=np.int32))
    layer = mesh.uv_layers.new(name="Checker")
    square = np.array([[0, 0], [1, 0], [1, 1], [0, 1]], dtype=np.float32)
    uv = np.concatenate([square + [f, f % 2] for f in range(6)]).astype(np.float32)
    layer.uv.foreach_set("vector", uv.reshape(-1))
    mesh.update()
    return src


def loop_uvs(mesh, name):
    uv = np.empty(len(mesh.loops) * 2, dtype=np.float32)
    mesh.uv_layers[name].uv.foreach_get("vector", uv)
    return uv.reshape(-1, 2)


def check_checker_uvs(uv, src_uv, st, loop_face, loop_corner, faces):
    """The keep-corners rule on the checker cube, per output loop (`faces`: the output faces'
    vertex indices, flattened in loop order): the cage corners' own UVs at (σ, τ) = (0, 0), the
    face's mean UV at (1, 1) with every face met, one UV per (output vertex, cage face), and each
    face's UVs inside its square."""
    at = (st == 0).all(axis=1)
    assert np.allclose(uv[at], src_uv[4 * loop_face[at] + loop_corner[at]], atol=1e-6)
    at = (st == 1).all(axis=1)
    assert set(loop_face[at].tolist()) == set(range(6))
    centres = src_uv.reshape(6, 4, 2).mean(axis=1)
    assert np.allclose(uv[at], centres[loop_face[at]], atol=1e-6)
    verts = np.asarray(faces, dtype=np.int64).reshape(-1)
    seen = {}
    for v, f, u in zip(verts.tolist(), loop_face.tolist(), uv.tolist()):
        prev = seen.setdefault((v, f), u)
        assert np.allclose(prev, u, atol=1e-6), (v, f, prev, u)
    lo = np.array([[f, f % 2] for f in range(6)], dtype=np.float32)[loop_face]
    assert ((uv >= lo - 1e-6) & (uv <= lo + 1 + 1e-6)).all()


@pytest.mark.parametrize("method", STRUCTURES)
def test_materials_and_uvs_follow_the_cage(method):
    src = cube_with_materials_and_checker()
    assert bpy.ops.object.gbsurf_convert(method=method, resolution=2) == {'FINISHED'}
    out = bpy.context.active_object
    mesh = out.data
    # The source's materials, per face from its cage face.
    assert [m.name for m in mesh.materials] == ["A", "B"]
    lib_options, outputs = mod().core.split_options({"method": method, "resolution": 2})
    conv = mod().core.compute(src, lib_options, outputs)
    nq = len(conv.quads)
    assert len(mesh.polygons) == nq == 6 * 4 * 4
    cage_face = conv.cage_corner[:, 0].astype(np.int64)
    mi = np.empty(nq, dtype=np.int32)
    mesh.polygons.foreach_get("material_index", mi)
    src_mi = np.array([0, 0, 0, 1, 1, 1])
    assert (mi == src_mi[cage_face]).all()
    assert (mi == 1).sum() == (mi == 0).sum() == 3 * 16
    # Every source UV map, the active one kept.
    names = [layer.name for layer in src.data.uv_layers]
    assert [layer.name for layer in mesh.uv_layers] == names
    assert mesh.uv_layers.active.name == src.data.uv_layers.active.name
    uv = loop_uvs(mesh, "Checker")
    src_uv = loop_uvs(src.data, "Checker")
    st = conv.cage_coords
    corner = conv.cage_corner[:, 1].astype(np.int64)
    loop_face, loop_corner = np.repeat(cage_face, 4), np.repeat(corner, 4)
    # At the cage corners: the source's corner UV (faces are quads, 4 corners each).
    at = (st == 0).all(axis=1)
    assert at.sum() == 24
    check_checker_uvs(uv, src_uv, st, loop_face, loop_corner, conv.quads)


@pytest.mark.parametrize("method", STRUCTURES)
def test_triangle_layout_carries_materials_and_uvs(method):
    # The triangle layout at r = 4 (the quad layout's 2r = 4 steps per side): every triangle
    # corner has its own cage corner and coordinates (a triangle can straddle two sectors).
    src = cube_with_materials_and_checker()
    opts = {"method": method, "resolution": 4, "face_layout": "TRIANGLES"}
    assert bpy.ops.object.gbsurf_convert(**opts) == {'FINISHED'}
    mesh = bpy.context.active_object.data
    assert [m.name for m in mesh.materials] == ["A", "B"]
    lib_options, outputs = mod().core.split_options(opts)
    conv = mod().core.compute(src, lib_options, outputs)
    assert mod().core.VERTEX_GROUPS_SKIPPED not in conv.warnings
    nt = len(conv.triangles)
    assert len(conv.quads) == 0 and len(mesh.polygons) == nt == 6 * 4 * 16
    assert len(conv.cage_coords) == len(conv.cage_loop_corner) == len(mesh.loops) == 3 * nt
    mi = np.empty(nt, dtype=np.int32)
    mesh.polygons.foreach_get("material_index", mi)
    assert (mi == np.array([0, 0, 0, 1, 1, 1])[conv.cage_corner[:, 0].astype(np.int64)]).all()
    assert [layer.name for layer in mesh.uv_layers] == [layer.name for layer in src.data.uv_layers]
    uv = loop_uvs(mesh, "Checker")
    src_uv = loop_uvs(src.data, "Checker")
    st = conv.cage_coords
    loop_face = conv.cage_loop_corner[:, 0].astype(np.int64)
    loop_corner = conv.cage_loop_corner[:, 1].astype(np.int64)
    # Some loops lie in another cage corner than their triangle's (the dual structure: another
    # cage face).
    differs = (conv.cage_loop_corner != np.repeat(conv.cage_corner, 3, axis=0)).any(axis=1)
    assert differs.any()
    # At the cage corners: the source's corner UV, every one of the 24 corners met.
    at = (st == 0).all(axis=1)
    assert len(set(zip(loop_face[at].tolist(), loop_corner[at].tolist()))) == 24
    check_checker_uvs(uv, src_uv, st, loop_face, loop_corner, conv.triangles)


def test_source_without_materials_keeps_the_colour_material():
    helpers.add_primitive("cube")
    assert bpy.ops.object.gbsurf_convert(method='TOPOLOGY', resolution=2) == {'FINISHED'}
    out = bpy.context.active_object
    assert [m.name for m in out.data.materials] == [mod().core.MATERIAL_NAME]


def test_cage_loop_values_is_the_keep_corners_rule():
    # One quad face with corner values 0, 1, 2, 3: corner, edge midpoints, centre.
    values = np.array([[0.0], [1.0], [2.0], [3.0]])
    unknown = 0xFFFFFFFF
    corner = np.array([[0, 1], [0, unknown], [unknown, 0]], dtype=np.uint32)
    coords = np.array([[0, 0], [1, 0], [1, 1], [0, 1]] * 3, dtype=np.float64)
    out = mod().mesh_io.cage_loop_values(values, [4], corner, coords)
    assert out[:4, 0].tolist() == [1.0, 1.5, 1.5, 0.5]
    assert out[4:, 0].tolist() == [0.0] * 8  # unknown corner, unknown face
    # A corner the cage does not have (sizes of another cage) is an error naming it.
    for bad, word in (([[0, 7]], "corner 7"), ([[5, 0]], "cage face 5")):
        with pytest.raises(mod().native.GbsurfError, match=word):
            mod().mesh_io.cage_loop_values(values, [4], np.array(bad, dtype=np.uint32), coords[:4])
    # Per-loop cage corners (the triangle layout) take the place of the face's.
    loops = np.array([[0, 1], [0, 2], [0, 3], [0, unknown]], dtype=np.uint32)
    st = np.array([[0, 0]] * 4, dtype=np.float64)
    out = mod().mesh_io.cage_loop_values(values, [4], [[0, 0]], st, loops)
    assert out[:, 0].tolist() == [1.0, 2.0, 3.0, 0.0]
