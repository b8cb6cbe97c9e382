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
    with pytest.raises(RuntimeError, match=fragment):
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
