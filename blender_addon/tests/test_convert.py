"""The Convert operator on the shared models and Blender's primitives, both structures, with the
MeshLab checks on every output and the Hausdorff distance to Blender's Subdivision Surface."""

import re
import time

import bpy
import numpy as np
import pytest

import helpers
from conftest import METRICS, ensure_enabled

import meshcheck  # noqa: E402  (after bpy, see conftest)
import pymeshlab  # noqa: E402

RESOLUTION = 4
MODEL_FILES = sorted(p.name for p in helpers.MODELS.glob("*.obj"))
STRUCTURES = ["DUAL", "TOPOLOGY"]


def hausdorff(a_pos, a_tri, b_pos, b_tri):
    """Symmetric Hausdorff distance (max of both one-sided maxima) and the mean, by pymeshlab."""
    ms = pymeshlab.MeshSet()
    ms.add_mesh(pymeshlab.Mesh(vertex_matrix=a_pos, face_matrix=a_tri.astype(np.int32)))
    ms.add_mesh(pymeshlab.Mesh(vertex_matrix=b_pos, face_matrix=b_tri.astype(np.int32)))
    ab = ms.get_hausdorff_distance(sampledmesh=0, targetmesh=1, samplenum=20000)
    ba = ms.get_hausdorff_distance(sampledmesh=1, targetmesh=0, samplenum=20000)
    return max(ab["max"], ba["max"]), 0.5 * (ab["mean"] + ba["mean"])


def convert_and_check(src, method, label):
    closed = not helpers.has_boundary(src.data)
    # Separate shells of the input that already pass through each other (Suzanne's eyes and
    # head) may still do so in the output; no shell may intersect itself.
    src_rep = meshcheck.check_arrays(*helpers.mesh_arrays(src.data))
    shells_may_intersect = (src_rep.self_intersecting_faces > 0
                            and src_rep.self_intersecting_faces_within_shells == 0)
    src_before = helpers.snapshot()["objects"][src.name]
    t0 = time.perf_counter()
    assert bpy.ops.object.gbsurf_convert(method=method, resolution=RESOLUTION) == {'FINISHED'}
    seconds = time.perf_counter() - t0
    out = bpy.context.active_object
    assert out.name == src.name + ".GB" and out is not src
    assert helpers.snapshot()["objects"][src.name] == src_before, "the source changed"
    s = out.gbsurf
    assert s.is_result and s.source == src and s.method == method and s.resolution == RESOLUTION
    mesh = out.data
    nv = len(mesh.vertices)
    for name in ("gb_patch", "gb_mean_curvature", "gb_g1_deviation", "gb_curvature_color"):
        assert name in mesh.attributes and len(mesh.attributes[name].data) == nv, name
    assert mesh.color_attributes.active_color.name == "gb_curvature_color"
    # Only the displayed colour layer is built with the mesh; the others when first shown.
    assert "gb_g1_color" not in mesh.attributes and "gb_patch_color" not in mesh.attributes
    smooth = np.empty(len(mesh.polygons), dtype=bool)
    mesh.polygons.foreach_get("use_smooth", smooth)
    assert smooth.all()
    pos, tri = helpers.mesh_arrays(mesh)
    rep = meshcheck.check_arrays(pos, tri)
    problems = rep.problems(expect_closed=closed, shells_may_intersect=shells_may_intersect)
    assert not problems, f"{label}: {problems}"
    if closed:
        assert rep.closed and rep.boundary_edges == 0 and rep.volume > 0
    # Distance to Blender's Catmull-Clark limit (level 3), relative to the bounding-box diagonal.
    ref_pos, ref_tri = helpers.subsurf_arrays(src, 3)
    diag = float(np.linalg.norm(ref_pos.max(0) - ref_pos.min(0)))
    hmax, hmean = hausdorff(pos, tri, ref_pos, ref_tri)
    METRICS.append(
        f"{label:28s} {method:9s} {len(tri):7d} tris {seconds:6.2f} s  "
        f"Hausdorff to Subdivision Surface: max {hmax / diag:.4f}, mean {hmean / diag:.5f} (x diag)")
    return out


@pytest.mark.parametrize("method", STRUCTURES)
@pytest.mark.parametrize("model", MODEL_FILES)
def test_shared_models(model, method):
    src = helpers.load_model(helpers.MODELS / model)
    convert_and_check(src, method, model)


def _primitive_cases():
    for name in helpers.PRIMITIVES:
        for method in STRUCTURES:
            yield pytest.param(name, method, id=f"{name}-{method}")


@pytest.mark.parametrize("primitive,method", list(_primitive_cases()))
def test_blender_primitives(primitive, method):
    src = helpers.add_primitive(primitive)
    src.location = (1.0, 2.0, 3.0)
    src.rotation_euler = (0.3, 0.0, 0.5)
    bpy.context.view_layer.update()
    out = convert_and_check(src, method, primitive)
    assert np.allclose(np.array(out.matrix_world), np.array(src.matrix_world))
    # Every default primitive gives a valid surface in both structures (the cone's base cap, which
    # turns by more than a right angle from its rim, was once reported folded: docs/math.md#fold-centre).
    assert "NOT VALID" not in out.gbsurf.info, out.gbsurf.info


@pytest.mark.parametrize("method", ["DOO_SABIN", "CATMULL_CLARK"])
def test_subdivision_methods(method):
    src = helpers.add_primitive("cube")
    assert bpy.ops.object.gbsurf_convert(method=method, levels=2) == {'FINISHED'}
    out = bpy.context.active_object
    pos, tri = helpers.mesh_arrays(out.data)
    assert not meshcheck.check_arrays(pos, tri).problems(expect_closed=True)
    assert out.gbsurf.method == method and out.gbsurf.levels == 2
    assert src.gbsurf.is_result is False


def test_curve_network_and_control_nets():
    src = helpers.add_primitive("cube")
    assert bpy.ops.object.gbsurf_convert(
        method='DUAL', resolution=3, want_curves=True, want_control_net=True) == {'FINISHED'}
    out = bpy.context.active_object
    cu, net = out.gbsurf.curves_object, out.gbsurf.net_object
    assert cu is not None and cu.type == 'CURVE' and cu.parent == out
    assert len(cu.data.splines) == 12  # the dual of a cube: 12 boundary curves
    assert all(sp.type == 'BEZIER' and len(sp.bezier_points) == 2 for sp in cu.data.splines)
    assert net is not None and net.type == 'MESH' and len(net.data.polygons) > 0
    assert src.name + ".GB.curves" == cu.name
    # Both are copies of the library's derived geometry.
    mod = helpers.mesh_module()
    pos, faces = helpers.mesh_arrays(src.data)[0], [list(p.vertices) for p in src.data.polygons]
    sizes = np.array([len(f) for f in faces], np.uint32)
    idx = np.array([i for f in faces for i in f], np.uint32)
    conv = mod.native.convert(pos, sizes, idx, mod.native.make_options(resolution=3),
                              want_curves=True, want_control_net=True)
    cn = conv.control_net
    assert len(net.data.vertices) == len(cn["positions"])
    assert len(net.data.polygons) == len(cn["face_sizes"]) == len(cn["face_indices"]) // 4
    spokes = {tuple(sorted(e)) for e in cn["edges"].tolist()}
    assert len(spokes) == 3 * 8 and spokes <= {tuple(sorted(e.vertices)) for e in net.data.edges}
    assert list(net.data.attributes["gb_patch"].data[i].value for i in range(3)) == cn["patch"][:3].tolist()
    for sp, chain in zip(cu.data.splines, conv.curves):
        a, b = sp.bezier_points
        got = np.array([a.co, a.handle_right, b.handle_left, b.co])
        assert np.allclose(got, chain, atol=1e-6)


def test_several_selected_objects():
    a = helpers.add_primitive("cube")
    b = helpers.add_primitive("ico_sphere")
    helpers.select_only(a, b)
    assert bpy.ops.object.gbsurf_convert(resolution=3) == {'FINISHED'}
    assert {"cube.GB", "ico_sphere.GB"} <= set(bpy.data.objects.keys())
    assert set(o.name for o in bpy.context.selected_objects) == {"cube.GB", "ico_sphere.GB"}


def test_convert_object_function():
    mod = helpers.mesh_module()
    src = helpers.add_primitive("cube")
    out = mod.core.convert_object(src, method='TOPOLOGY', resolution=3)
    assert out.name == "cube.GB" and out.gbsurf.method == 'TOPOLOGY'
    with pytest.raises(mod.core.ConvertError, match="unknown option"):
        mod.core.convert_object(src, resolutoin=3)
    with pytest.raises(mod.core.ConvertError, match="cancelled"):
        mod.core.convert_object(src, progress=lambda f: f < 0.1)
    assert [o.name for o in bpy.data.objects].count("cube.GB.001") == 0


def test_select_all_converts_only_control_meshes():
    # After a conversion with extras, "select all, convert" (with a non-mesh object among them)
    # converts the control mesh again, never the results or their control nets.
    helpers.add_primitive("cube")
    assert bpy.ops.object.gbsurf_convert(
        resolution=2, want_curves=True, want_control_net=True) == {'FINISHED'}
    bpy.ops.object.text_add()
    bpy.ops.object.select_all(action='SELECT')
    assert bpy.ops.object.gbsurf_convert(resolution=2) == {'FINISHED'}
    names = set(bpy.data.objects.keys())
    assert "cube.GB.001" in names
    assert not any(n.endswith(".GB.GB") or ".net.GB" in n for n in names), names
    # Only results selected: nothing to convert.
    helpers.select_only(bpy.data.objects["cube.GB"], bpy.data.objects["cube.GB.net"])
    with helpers.refused("poll"):
        bpy.ops.object.gbsurf_convert()


def _linked_collection(tmp_path):
    """A collection linked from another .blend (read-only here) holding a cube, in the scene."""
    src = helpers.add_primitive("cube")
    col = bpy.data.collections.new("LibCol")
    bpy.context.scene.collection.children.link(col)
    for c in list(src.users_collection):
        c.objects.unlink(src)
    col.objects.link(src)
    lib = tmp_path / "lib.blend"
    bpy.ops.wm.save_as_mainfile(filepath=str(lib), copy=True)
    bpy.ops.wm.read_factory_settings(use_empty=True)
    ensure_enabled()  # reading factory settings disables the extension
    with bpy.data.libraries.load(str(lib), link=True) as (_src, dst):
        dst.collections = ["LibCol"]
    bpy.context.scene.collection.children.link(dst.collections[0])
    bpy.context.view_layer.update()
    return dst.collections[0]


def test_source_in_a_linked_collection(tmp_path):
    col = _linked_collection(tmp_path)
    src = bpy.data.objects["cube"]
    assert src.library is not None
    helpers.select_only(src)
    assert bpy.ops.object.gbsurf_convert(resolution=2) == {'FINISHED'}
    out = bpy.data.objects["cube.GB"]
    assert out.library is None and out.gbsurf.source == src
    assert out.name in bpy.context.scene.collection.objects and out.name not in col.objects


def _crease_all_edges(obj, value=1.0):
    attr = obj.data.attributes.get("crease_edge") or obj.data.attributes.new("crease_edge", 'FLOAT', 'EDGE')
    attr.data.foreach_set("value", np.full(len(obj.data.edges), value, dtype=np.float32))


@pytest.mark.parametrize("method", ['TOPOLOGY', 'DUAL'])
def test_cube_with_crease_edge_one_keeps_its_corners(method):
    mod = helpers.mesh_module()
    src = helpers.add_primitive("cube")
    _crease_all_edges(src)
    data = mod.mesh_io.read_mesh(src.data)
    ev, es, vv, vs = data.creases
    assert ev.shape == (12, 2) and es.tolist() == [1.0] * 12 and len(vv) == 0 and len(vs) == 0
    out = mod.core.convert_object(src, method=method, resolution=4)
    pos, _ = helpers.mesh_arrays(out.data)
    assert np.abs(pos).max() <= 1.0 + 1e-6
    for corner in np.array([[x, y, z] for x in (-1, 1) for y in (-1, 1) for z in (-1, 1)], float):
        assert np.linalg.norm(pos - corner, axis=1).min() <= 1e-6, corner
    # every output vertex lies on the cube (the faces stay flat)
    assert (np.abs(np.abs(pos) - 1.0) <= 1e-6).any(axis=1).all()
    # crease 0 is the smooth surface again (bit-identical positions)
    _crease_all_edges(src, 0.0)
    assert mod.mesh_io.read_mesh(src.data).creases is None
    smooth = mod.core.convert_object(src, method=method, resolution=4)
    pos = helpers.mesh_arrays(smooth.data)[0]
    assert np.linalg.norm(np.abs(pos) - 1.0, axis=1).min() > 0.1  # the corners are rounded off


@pytest.mark.parametrize("method,start", [('TOPOLOGY', 0.0), ('DUAL', 0.05)])
def test_semi_sharp_crease_sweep_moves_the_surface_a_little_per_step(method, start):
    """An animated crease: the top loop of Blender's cube swept from `start` to 1 in steps of
    0.05 through `crease_edge`. The output keeps its vertex count and each step moves every
    vertex by less than 0.05 (the cube has edge 2). The dual structure starts at 0.05: it splits
    its patches as soon as c > 0 (docs/math.md#dual-creases), a step of its own (0.054 in the
    library's test)."""
    mod = helpers.mesh_module()
    src = helpers.add_primitive("cube")
    co = np.empty(3 * len(src.data.vertices), dtype=np.float32)
    src.data.vertices.foreach_get("co", co)
    top = co.reshape(-1, 3)[:, 2] > 0
    ev = np.empty(2 * len(src.data.edges), dtype=np.int32)
    src.data.edges.foreach_get("vertices", ev)
    loop = top[ev.reshape(-1, 2)].all(axis=1)
    assert loop.sum() == 4
    attr = src.data.attributes.new("crease_edge", 'FLOAT', 'EDGE')
    prev, first, worst = None, None, 0.0
    for k in range(round(start / 0.05), 21):
        attr.data.foreach_set("value", np.where(loop, 0.05 * k, 0.0).astype(np.float32))
        src.data.update()
        out = mod.core.convert_object(src, method=method, resolution=2)
        pos = helpers.mesh_arrays(out.data)[0]
        bpy.data.objects.remove(out)
        if prev is not None:
            assert pos.shape == prev.shape, k
            step = np.linalg.norm(pos - prev, axis=1).max()
            worst = max(worst, step)
            assert step < 0.05, (k, step)
        prev = pos
        first = pos if first is None else first
    # ... and the whole sweep does change the surface (the crease is read at all)
    assert np.linalg.norm(prev - first, axis=1).max() > 0.2


def test_a_folded_result_says_so_and_marks_the_fold():
    """OpenSubdiv's bishop (without its crease tags): its dual report at resolution 3 counts 2
    folded patches and 5 self-intersecting pairs. The result's info says NOT VALID with the
    report's figures, and `gb_fold` marks vertices; the plain cube has no mark. A borderline
    fixture: the 2 folds are dual patches 844 and 846, next to the cage vertex 844 where the
    topology structure is refused, so a change to the construction may clear them; hence only a
    fold at all is asserted, not its count. (The rook without
    its tags served here until the direction blends were kept on their side of the curve,
    docs/math.md#blend-side, which removed its 24 folds; before it, a cube with a corner pulled
    inside, until the fold rule's blended reference.)"""
    verts = [(0, 0, 0), (1, 0, 0), (1, 1, 0), (0, 1, 0), (0, 0, 1), (1, 0, 1), (1, 1, 1), (0, 1, 1)]
    faces = [(0, 3, 2, 1), (4, 5, 6, 7), (0, 1, 5, 4), (1, 2, 6, 5), (2, 3, 7, 6), (3, 0, 4, 7)]
    bishop_pos, bishop_faces = helpers.parse_obj(helpers.ROOT / "tests/data/opensubdiv/catmark_bishop.obj")
    for name, v, f, folded in (("plain", verts, faces, False), ("bishop", bishop_pos, bishop_faces, True)):
        src = helpers.add_mesh_object(name, v, f)
        helpers.select_only(src)
        assert bpy.ops.object.gbsurf_convert(method='DUAL', resolution=3) == {'FINISHED'}
        out = bpy.context.active_object
        fold = np.empty(len(out.data.vertices), np.float32)
        out.data.attributes["gb_fold"].data.foreach_get("value", fold)
        if folded:
            assert "NOT VALID" in out.gbsurf.info and "folded patches" in out.gbsurf.info, out.gbsurf.info
            assert fold.max() == 1.0 and fold.sum() < len(fold)
            # The cage is checked only when the output self-intersects; else the info says so.
            m = re.search(r"(\d+) self-intersecting triangle pairs \(input cage: (not checked|\d+)\)", out.gbsurf.info)
            assert m and (m.group(2) == "not checked") == (m.group(1) == "0"), out.gbsurf.info
        else:
            assert "NOT VALID" not in out.gbsurf.info, out.gbsurf.info
            assert fold.max() == 0.0


def test_convex_regions_are_coloured_warm():
    # The stored mean curvature keeps the library's sign (H < 0 on convex regions); the colour
    # map shows convex red-dominant and concave blue-dominant (as MeshLab's curvature maps).
    src = helpers.add_primitive("ico_sphere")
    assert bpy.ops.object.gbsurf_convert(resolution=3) == {'FINISHED'}
    mesh = bpy.context.active_object.data
    n = len(mesh.vertices)
    h = np.empty(n, dtype=np.float32)
    mesh.attributes["gb_mean_curvature"].data.foreach_get("value", h)
    assert (h < 0).all()  # the sign stays
    rgba = np.empty(n * 4, dtype=np.float32)
    mesh.attributes["gb_curvature_color"].data.foreach_get("color", rgba)
    rgba = rgba.reshape(-1, 4)
    assert (rgba[:, 0] >= rgba[:, 2]).all() and (rgba[:, 0] - rgba[:, 2]).mean() > 0.3
    # A fat torus (minor radius > major / 2) has H > 0 around its inner equator: blue-dominant.
    bpy.ops.mesh.primitive_torus_add(major_radius=1.0, minor_radius=0.75, major_segments=24,
                                     minor_segments=12)
    assert bpy.ops.object.gbsurf_convert(resolution=3) == {'FINISHED'}
    mesh = bpy.context.active_object.data
    rgba = np.empty(len(mesh.vertices) * 4, dtype=np.float32)
    mesh.attributes["gb_curvature_color"].data.foreach_get("color", rgba)
    rgba = rgba.reshape(-1, 4)
    h = np.empty(len(mesh.vertices), dtype=np.float32)
    mesh.attributes["gb_mean_curvature"].data.foreach_get("value", h)
    assert (h > 0).any() and (rgba[h > 0, 2] >= rgba[h > 0, 0]).all()
    assert (rgba[h > 0, 2] - rgba[h > 0, 0]).max() > 0.3
