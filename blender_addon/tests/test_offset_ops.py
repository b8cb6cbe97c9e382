"""The exact offset operators: `object.gbsurf_offset` (GB offset surface, checked with MeshLab)
and `curve.gbsurf_ph_offset` (PH quintic spline as an order-6 NURBS curve and its exact offset as a
poly curve, checked against the C ABI); bad input is refused with an error and creates nothing."""

import json

import bpy
import numpy as np
import pytest

import helpers

import meshcheck  # noqa: E402  (after bpy, see conftest)


def offset_module():
    return helpers.mesh_module().offset_ops


def run_offset(**kw):
    assert bpy.ops.object.gbsurf_offset(**kw) == {'FINISHED'}
    return bpy.context.active_object


@pytest.mark.parametrize("name,distance,shell", [
    ("cube", 0.1, True), ("cube", -0.1, False), ("torus", 0.05, True), ("torus", 0.05, False)])
def test_offset_surface_is_closed_two_manifold(name, distance, shell):
    src = helpers.add_primitive(name)
    before = helpers.snapshot()["objects"][src.name]
    out = run_offset(offset_distance=distance, offset_shell=shell, offset_grid=4)
    assert out is not src and out.name == src.name + ".offset"
    assert helpers.snapshot()["objects"][src.name] == before, "the source changed"
    s = out.gbsurf
    assert s.is_offset and not s.is_result and s.source == src
    assert s.offset_distance == pytest.approx(distance) and s.offset_shell == shell and s.offset_grid == 4
    assert "max gap" in s.info and "cusps" in s.info and "singular pieces" in s.info and "fit error" in s.info
    rep = meshcheck.check_arrays(*helpers.mesh_arrays(out.data))
    assert rep.closed and rep.two_manifold and rep.coherently_oriented, rep
    assert rep.duplicate_vertices == 0 and rep.zero_area_faces == 0, rep
    assert rep.connected_components == (2 if shell else 1), rep


def test_offset_of_a_result_uses_its_source_and_options_and_updates():
    src = helpers.add_primitive("cube")
    assert bpy.ops.object.gbsurf_convert(method='TOPOLOGY', resolution=4) == {'FINISHED'}
    gb = bpy.context.active_object
    out = run_offset(offset_distance=0.2)
    assert out.gbsurf.source == src and out.gbsurf.method == 'TOPOLOGY'
    nv = len(out.data.vertices)
    # Update regenerates from the stored settings (a shell has both sheets: more vertices).
    out.gbsurf.offset_shell = True
    assert bpy.ops.object.gbsurf_offset_update() == {'FINISHED'}
    assert len(out.data.vertices) > nv and out.gbsurf.source == src and gb.gbsurf.is_result
    rep = meshcheck.check_arrays(*helpers.mesh_arrays(out.data))
    assert rep.closed and rep.two_manifold, rep


def expect_error(op, fragment, **kw):
    before = helpers.snapshot()
    with helpers.refused(fragment):
        op(**kw)
    assert helpers.snapshot() == before, "a refused operator created or changed data"


def test_offset_surface_bad_input():
    helpers.add_primitive("cube")
    expect_error(bpy.ops.object.gbsurf_offset, "distance", offset_distance=0.0)
    bpy.ops.curve.primitive_bezier_circle_add()
    expect_error(bpy.ops.object.gbsurf_offset, "select a mesh object", offset_distance=0.1)


def ph_objects(src):
    return bpy.data.objects[src.name + ".PH"], bpy.data.objects[src.name + ".PH_offset"]


def test_ph_offset_of_a_bezier_circle():
    bpy.ops.curve.primitive_bezier_circle_add(radius=2.0)
    src = bpy.context.active_object
    d, density = 0.25, 16
    before = helpers.snapshot()["objects"][src.name]
    assert bpy.ops.curve.gbsurf_ph_offset(distance=d, density=density) == {'FINISHED'}
    assert helpers.snapshot()["objects"][src.name] == before
    ph, off = ph_objects(src)
    mod = helpers.mesh_module()
    on, om = mod.offset_native, offset_module()

    # The PH spline through the circle's points and handle tangents, from the C ABI.
    points, d_out, d_in, cyclic = om.bezier_hermite_data(src.data.splines[0])
    assert cyclic and len(points) == 4
    segs = om.ph_spline(points[:, :2], d_out[:, :2], d_in[:, :2], cyclic, src.name)
    try:
        cps = [s.control_points.copy() for s in segs]
        rationals = [s.offset(d)[:2] for s in segs]
    finally:
        for s in segs:
            s.free()

    # (a) Order-6 NURBS with Bezier knots: 5m + 1 control points, the quintics' own.
    sp = ph.data.splines[0]
    assert sp.type == 'NURBS' and sp.order_u == 6 and sp.use_endpoint_u and sp.use_bezier_u
    co = np.empty(4 * len(sp.points), dtype=np.float32)
    sp.points.foreach_get("co", co)
    co = co.reshape(-1, 4)
    assert len(co) == 5 * len(segs) + 1
    np.testing.assert_allclose(co[:, :2], om.nurbs_quintic_points(segs), atol=1e-6)
    assert (co[:, 3] == 1).all()
    # Blender's evaluation of that NURBS lies on the PH spline (wrong knots would not).
    dense = np.vstack([on.bezier_eval(c, np.linspace(0, 1, 1001)) for c in cps])
    ev = ph.evaluated_get(bpy.context.evaluated_depsgraph_get())
    mesh = ev.to_mesh()
    try:
        vco = np.empty(3 * len(mesh.vertices), dtype=np.float32)
        mesh.vertices.foreach_get("co", vco)
    finally:
        ev.to_mesh_clear()
    vco = vco.reshape(-1, 3)[:, :2].astype(np.float64)
    assert len(vco) >= 4 * len(segs)
    # Distance to the dense polyline (chord error < 1e-6 at 1000 samples per quarter circle).
    a, b = dense[:-1], dense[1:]
    ab = b - a
    u = np.clip(np.einsum("vsk,sk->vs", vco[:, None, :] - a[None], ab) / np.einsum("sk,sk->s", ab, ab), 0, 1)
    near = np.linalg.norm(vco[:, None, :] - (a[None] + u[..., None] * ab[None]), axis=2).min(axis=1)
    assert near.max() < 1e-5, near.max()

    # (b) The offset poly curve: exact rational points at distance |d| from the PH spline.
    osp = off.data.splines[0]
    assert osp.type == 'POLY' and len(osp.points) == density * len(segs) + 1
    record = json.loads(off[om.PH_OFFSET_PROPERTY])
    assert record["degree"] == 9 and record["distance"] == pytest.approx(d)
    assert len(record["segments"]) == len(segs) and record["cusps"] == []
    t = np.linspace(0.0, 1.0, density + 1)
    exact = []
    for k, ((p, w), c) in enumerate(zip(rationals, cps)):
        np.testing.assert_array_equal(np.array(record["segments"][k]["points"]), p)
        np.testing.assert_array_equal(np.array(record["segments"][k]["weights"]), w)
        o = on.rational_eval(p, w, t)
        r, dr = on.bezier_eval(c, t), on.bezier_derivative(c, t)
        dist = np.linalg.norm(o - r, axis=1)
        assert np.abs(dist - abs(d)).max() <= 1e-9 * abs(d), np.abs(dist - abs(d)).max()
        cosang = np.einsum("ij,ij->i", o - r, dr) / (dist * np.linalg.norm(dr, axis=1))
        assert np.abs(cosang).max() <= 1e-9
        exact.append(o if k == 0 else o[1:])
    exact = np.vstack(exact)
    pco = np.empty(4 * len(osp.points), dtype=np.float32)
    osp.points.foreach_get("co", pco)
    np.testing.assert_array_equal(pco.reshape(-1, 4)[:, :2], exact.astype(np.float32))


def test_ph_offset_reports_cusps():
    # An ellipse (semi-axes 2, 1: radii of curvature 0.5 .. 4) offset inward by 1: the offset
    # has cusps where the radius of curvature equals 1; they are reported, never hidden.
    bpy.ops.curve.primitive_bezier_circle_add(radius=1.0)
    src = bpy.context.active_object
    for bp in src.data.splines[0].bezier_points:
        bp.handle_left_type = bp.handle_right_type = 'FREE'
        bp.co.x, bp.handle_left.x, bp.handle_right.x = 2 * bp.co.x, 2 * bp.handle_left.x, 2 * bp.handle_right.x
    counts = []
    for d in (1.0, -1.0):
        helpers.select_only(src)
        assert bpy.ops.curve.gbsurf_ph_offset(distance=d, density=8) == {'FINISHED'}
        _, off = ph_objects(src)
        record = json.loads(off[offset_module().PH_OFFSET_PROPERTY])
        counts.append(len(record["cusps"]))
        assert all(0.0 <= t <= 1.0 for _, t in record["cusps"])
        bpy.data.objects.remove(off)
        bpy.data.objects.remove(bpy.data.objects[src.name + ".PH"])
        bpy.context.view_layer.update()
    # Only the inward side reaches the radius of curvature.
    assert min(counts) == 0 and max(counts) >= 2, counts


def test_ph_offset_bad_input():
    bpy.ops.curve.primitive_bezier_circle_add()
    expect_error(bpy.ops.curve.gbsurf_ph_offset, "non-zero", distance=0.0)
    helpers.add_primitive("cube")
    expect_error(bpy.ops.curve.gbsurf_ph_offset, "select a Bezier curve", distance=0.1)
    cu = bpy.data.curves.new("zero", 'CURVE')
    sp = cu.splines.new('BEZIER')
    sp.bezier_points.add(1)
    for bp in sp.bezier_points:
        bp.co = bp.handle_left = bp.handle_right = (0.0, 0.0, 0.0)
    ob = bpy.data.objects.new("zero", cu)
    bpy.context.scene.collection.objects.link(ob)
    helpers.select_only(ob)
    expect_error(bpy.ops.curve.gbsurf_ph_offset, "zero: segment 0", distance=0.1)


# --- live mode and menus ---------------------------------------------------------------------------

def _coords(mesh):
    co = np.empty(len(mesh.vertices) * 3, dtype=np.float32)
    mesh.vertices.foreach_get("co", co)
    return co.reshape(-1, 3)


def test_offset_surface_is_live_like_the_surface():
    """Live mode (handlers.py) regenerates an offset surface when its source's geometry, its own
    settings or (through an animated modifier) the frame change, through the path of GB results;
    without live mode nothing changes."""
    src = helpers.add_primitive("cube")
    mod = src.modifiers.new("displace", 'DISPLACE')  # no texture: a push along the normals
    mod.mid_level, mod.strength = 0.0, 0.0
    mod.keyframe_insert("strength", frame=1)
    mod.strength = 1.0
    mod.keyframe_insert("strength", frame=10)
    bpy.context.scene.frame_set(1)
    helpers.select_only(src)
    out = run_offset(offset_distance=0.1, offset_grid=3)
    assert out.gbsurf.source_digest, "the offset remembers the source it was made from"
    e1 = np.ptp(_coords(out.data), axis=0)
    handlers = helpers.mesh_module().handlers
    # Live off: a frame change does nothing (same mesh, same extents; a regeneration at frame 10
    # would push every side out by 1).
    mesh = out.data
    bpy.context.scene.frame_set(10)
    assert out.data == mesh
    assert np.allclose(np.ptp(_coords(out.data), axis=0), e1)
    bpy.context.scene.frame_set(1)
    out.gbsurf.live = True
    bpy.context.view_layer.update()
    # A frame whose evaluated source changed: regenerated (pushed out by 1 on every side).
    bpy.context.scene.frame_set(10)
    e10 = np.ptp(_coords(out.data), axis=0)
    assert np.all(e10 > e1 + 1.0), (e1, e10)
    assert "max gap" in out.gbsurf.info
    bpy.context.scene.frame_set(1)
    assert np.allclose(np.ptp(_coords(out.data), axis=0), e1, rtol=1e-5)
    # Its own settings: a larger distance, a shell (two sheets: more vertices).
    nv = len(out.data.vertices)
    out.gbsurf.offset_distance = 0.3
    bpy.context.view_layer.update()
    assert np.allclose(np.ptp(_coords(out.data), axis=0), e1 + 0.4, rtol=1e-3), np.ptp(_coords(out.data), axis=0)
    out.gbsurf.offset_shell = True
    bpy.context.view_layer.update()
    assert len(out.data.vertices) == 2 * nv
    rep = meshcheck.check_arrays(*helpers.mesh_arrays(out.data))
    assert rep.closed and rep.two_manifold and rep.connected_components == 2, rep
    # The source's edited geometry.
    out.gbsurf.offset_shell = False
    bpy.context.view_layer.update()
    e = np.ptp(_coords(out.data), axis=0)
    co = _coords(src.data) * 2.0
    src.data.vertices.foreach_set("co", co.reshape(-1))
    src.data.update()
    bpy.context.view_layer.update()
    assert np.all(np.ptp(_coords(out.data), axis=0) > 1.5 * e), (e, np.ptp(_coords(out.data), axis=0))
    # A moved source carries the offset along.
    src.location = (0.0, 4.0, 0.0)
    bpy.context.view_layer.update()
    assert tuple(out.matrix_world.translation) == pytest.approx((0.0, 4.0, 0.0))
    # Settled: another update changes nothing.
    mesh = out.data
    bpy.context.view_layer.update()
    assert out.data == mesh and not handlers._busy


def test_offset_live_error_is_stored_not_raised():
    src = helpers.add_primitive("cube")
    out = run_offset(offset_distance=0.1)
    out.gbsurf.live = True
    bpy.context.view_layer.update()
    mesh = out.data
    before = _coords(out.data)
    out.gbsurf.method = 'CATMULL_CLARK'  # not a patch method: the offset refuses it
    bpy.context.view_layer.update()
    assert out.data == mesh and np.array_equal(_coords(out.data), before)
    assert out.gbsurf.info.startswith("Live update failed") and "patch method" in out.gbsurf.info


class _Layout:
    def __init__(self, log):
        self.log = log

    def separator(self, **kw):
        pass

    def operator(self, idname, **kw):
        self.log.append((idname, kw.get("text")))


class _Menu:
    def __init__(self, log):
        self.layout = _Layout(log)


def test_ph_offset_is_in_the_curve_menus_and_works_from_edit_mode():
    ui = helpers.mesh_module().ui
    # Registered in the edit-mode Curve menu and the context menus (bpy 5.0 names), and still in
    # Object > Convert.
    for name in ui.CURVE_MENUS:
        assert ui.menu_curve in getattr(bpy.types, name)._dyn_ui_initialize(), name
    assert ui.menu_convert in bpy.types.VIEW3D_MT_object_convert._dyn_ui_initialize()
    bpy.ops.curve.primitive_bezier_circle_add(radius=2.0)
    src = bpy.context.active_object
    log = []
    ui.menu_curve(_Menu(log), bpy.context)
    assert log == [("curve.gbsurf_ph_offset", "Exact Offset (PH)")]
    # Only for curves (the object context menu is shared by every object type).
    cube = helpers.add_primitive("cube")
    log.clear()
    ui.menu_curve(_Menu(log), bpy.context)
    assert log == []
    helpers.select_only(src)
    # From Edit Mode (the Curve menu): the operator leaves Edit Mode and adds both curves.
    bpy.ops.object.mode_set(mode='EDIT')
    assert bpy.context.mode == 'EDIT_CURVE'
    assert bpy.ops.curve.gbsurf_ph_offset.poll()
    # A refused run (distance 0) leaves the user in Edit Mode, with nothing added.
    n_objects = len(bpy.data.objects)
    expect_error(bpy.ops.curve.gbsurf_ph_offset, "non-zero", distance=0.0)
    assert bpy.context.mode == 'EDIT_CURVE' and len(bpy.data.objects) == n_objects
    assert bpy.ops.curve.gbsurf_ph_offset(distance=0.25, density=8) == {'FINISHED'}
    assert bpy.context.mode == 'OBJECT'
    ph, off = ph_objects(src)
    assert ph.data.splines[0].order_u == 6 and len(off.data.splines[0].points) == 4 * 8 + 1
    assert cube.name in bpy.data.objects
