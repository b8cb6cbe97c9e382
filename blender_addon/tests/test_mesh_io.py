"""numpy mesh transfer: n-gons kept on input, triangles/n-gons/attributes written, colour maps."""

import bpy
import numpy as np

import helpers


def mio():
    return helpers.mesh_module().mesh_io


def test_read_cube_keeps_quads():
    obj = helpers.add_primitive("cube")
    pos, sizes, idx = mio().read_mesh(obj.data)
    assert pos.shape == (8, 3) and pos.dtype == np.float64
    assert sizes.tolist() == [4] * 6 and sizes.dtype == np.uint32
    assert len(idx) == 24 and idx.max() == 7
    assert np.allclose(np.abs(pos), 1.0)


def test_read_cylinder_and_cone_keep_ngons():
    cyl = helpers.add_primitive("cylinder")
    _, sizes, _ = mio().read_mesh(cyl.data)
    assert sorted(sizes.tolist()).count(32) == 2 and sizes.tolist().count(4) == 32
    cone = helpers.add_primitive("cone")
    _, sizes, _ = mio().read_mesh(cone.data)
    assert sizes.tolist().count(32) == 1 and sizes.tolist().count(3) == 32


def test_polygon_round_trip():
    pos = np.array([[0, 0, 0], [2, 0, 0], [3, 1, 0], [1, 3, 0], [-1, 1, 0], [1, 1, 2]], float)
    faces = [[0, 1, 2, 3, 4], [0, 5, 1], [1, 5, 2], [2, 5, 3], [3, 5, 4], [4, 5, 0]]
    obj = helpers.add_mesh_object("pent", pos, faces)
    p2, s2, i2 = mio().read_mesh(obj.data)
    assert np.allclose(p2, pos)
    assert s2.tolist() == [5, 3, 3, 3, 3, 3]
    assert i2.tolist() == [i for f in faces for i in f]
    assert obj.data.validate() is False  # nothing to fix


def test_evaluated_object_read_applies_modifiers():
    obj = helpers.add_primitive("cube")
    obj.modifiers.new("sub", 'SUBSURF').levels = 1
    pos, sizes, _ = mio().read_object(obj)
    assert len(sizes) == 24 and len(pos) == 26


def test_triangle_writer_and_attributes():
    pos = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]], float)
    tris = np.array([[0, 2, 1], [0, 1, 3], [1, 2, 3], [0, 3, 2]], np.uint32)
    mesh = bpy.data.meshes.new("tet")
    mio().write_triangles(mesh, pos, tris)
    assert len(mesh.vertices) == 4 and len(mesh.polygons) == 4 and len(mesh.edges) == 6
    p2, s2, i2 = mio().read_mesh(mesh)
    assert np.allclose(p2, pos) and i2.reshape(-1, 3).tolist() == tris.tolist()
    mio().set_point_attribute(mesh, "k", 'FLOAT', [0.5, -1.0, 2.0, 0.0])
    mio().set_point_attribute(mesh, "i", 'INT', [3, 1, 4, 1])
    mio().set_point_attribute(mesh, "c", 'FLOAT_COLOR', np.tile([0.1, 0.2, 0.3, 1.0], 4))
    assert np.allclose(mio().get_point_attribute(mesh, "k"), [0.5, -1.0, 2.0, 0.0])
    assert mio().get_point_attribute(mesh, "i").tolist() == [3, 1, 4, 1]
    assert np.allclose(mio().get_point_attribute(mesh, "c")[2], [0.1, 0.2, 0.3, 1.0])
    mio().set_point_attribute(mesh, "k", 'FLOAT', [1, 1, 1, 1])  # replaced, not duplicated
    assert [a.name for a in mesh.attributes].count("k") == 1
    # float32 in Blender: display values are clamped, positions beyond it are refused by vertex
    mio().set_point_attribute(mesh, "k", 'FLOAT', [1e39, -1e300, 0.5, 0.0])
    big = float(np.finfo(np.float32).max)
    assert mio().get_point_attribute(mesh, "k").tolist() == [big, -big, 0.5, 0.0]
    mio().shade_smooth(mesh)
    sm = np.empty(4, dtype=bool)
    mesh.polygons.foreach_get("use_smooth", sm)
    assert sm.all()


def test_quad_writer_and_face_materials():
    # The quad layout's faces: (Q,4) arrays become quads, material index per face.
    pos = np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0], [2, 0, 0], [2, 1, 0]], float)
    quads = np.array([[0, 1, 2, 3], [1, 4, 5, 2]], np.uint32)
    mesh = bpy.data.meshes.new("quads")
    mio().write_triangles(mesh, pos, quads)
    assert len(mesh.polygons) == 2 and len(mesh.loops) == 8 and len(mesh.edges) == 7
    p2, s2, i2 = mio().read_mesh(mesh)
    assert s2.tolist() == [4, 4] and i2.reshape(-1, 4).tolist() == quads.tolist()
    mio().set_face_materials(mesh, [0, 1])
    mi = np.empty(2, dtype=np.int32)
    mesh.polygons.foreach_get("material_index", mi)
    assert mi.tolist() == [0, 1]


def _edge_table(mesh):
    ev = np.empty(2 * len(mesh.edges), dtype=np.int32)
    mesh.edges.foreach_get("vertices", ev)
    ce = np.empty(len(mesh.loops), dtype=np.int32)
    mesh.loops.foreach_get("edge_index", ce)
    return ev.reshape(-1, 2), ce


def test_library_edge_table_is_what_blender_derives():
    """The converted torus built with the library's edges and corner edges (no calc_edges) is the
    mesh Blender derives itself: valid, the same set of edges, each corner on its own edge."""
    native = helpers.mesh_module().native
    src = helpers.add_primitive("torus")
    data = mio().read_mesh(src.data)
    for layout in ("QUADS", "TRIANGLES"):
        conv = native.convert(*data[:3], native.make_options(face_layout=layout, resolution=2))
        assert len(conv.corner_edges) == conv.faces.size and len(conv.edges)
        given = mio().write_triangles(bpy.data.meshes.new("given"), conv.positions, conv.faces,
                                      conv.edges, conv.corner_edges)
        derived = mio().write_triangles(bpy.data.meshes.new("derived"), conv.positions, conv.faces)
        assert not given.validate(verbose=False), "Blender had to correct the given edges"
        (eg, cg), (ed, cd) = _edge_table(given), _edge_table(derived)
        key = lambda e: set(map(tuple, np.sort(e, axis=1).tolist()))
        assert len(eg) == len(ed) and key(eg) == key(ed), layout
        # Each corner's edge joins its vertex and the next corner's, in both meshes.
        cv = np.empty(len(given.loops), dtype=np.int32)
        given.loops.foreach_get("vertex_index", cv)
        k = conv.faces.shape[1]
        nxt = cv.reshape(-1, k)[:, list(range(1, k)) + [0]].reshape(-1)
        want = np.sort(np.stack([cv, nxt], 1), axis=1)
        assert (np.sort(eg[cg], axis=1) == want).all() and (np.sort(ed[cd], axis=1) == want).all()


def test_colour_maps():
    c = mio().diverging_colors([-2.0, 0.0, 1.0, 2.0], scale=2.0)
    assert np.allclose(c[0, :3], [0, 0, 1]) and np.allclose(c[1, :3], [1, 1, 1])
    assert np.allclose(c[2, :3], [1, 0.5, 0.5]) and np.allclose(c[3, :3], [1, 0, 0])
    s = mio().sequential_colors([0.0, 0.5, 1.0, 5.0], vmax=1.0)
    assert np.allclose(s[0, :3], [0, 1, 0]) and np.allclose(s[1, :3], [1, 1, 0])
    assert np.allclose(s[2, :3], [1, 0, 0]) and np.allclose(s[3, :3], [1, 0, 0])
    ic = mio().index_colors([0, 1, 1, 2])
    assert np.allclose(ic[1], ic[2]) and not np.allclose(ic[0], ic[1])
    assert ((ic >= 0) & (ic <= 1)).all()
    nan = mio().diverging_colors([np.nan, 1.0])
    assert np.isfinite(nan).all()


def test_positions_beyond_float32_name_the_vertex():
    pos = np.array([[0, 0, 0], [1, 0, 0], [0, 1e39, 0], [0, 0, 1]], float)
    tris = np.array([[0, 2, 1], [0, 1, 3], [1, 2, 3], [0, 3, 2]], np.uint32)
    mesh = bpy.data.meshes.new("far")
    try:
        mio().write_triangles(mesh, pos, tris)
        raise AssertionError("expected Float32RangeError")
    except mio().Float32RangeError as e:
        assert "vertex 2: coordinate 1e+39" in str(e), e
    assert len(mesh.vertices) == 0  # refused before the mesh is touched
    pos[2, 1] = float(np.finfo(np.float32).max)  # the edge of the range is kept, finite
    mio().write_triangles(mesh, pos, tris)
    p2, _, _ = mio().read_mesh(mesh)
    assert np.isfinite(p2).all() and p2[2, 1] == pos[2, 1]
