"""Modifier-like behaviour: undo, Update, live mode, settings kept on the result."""

import bpy
import numpy as np
import pytest

import helpers


def coords(mesh):
    co = np.empty(len(mesh.vertices) * 3, dtype=np.float32)
    mesh.vertices.foreach_get("co", co)
    return co.reshape(-1, 3)


def scale_source(src, factor):
    co = coords(src.data) * factor
    src.data.vertices.foreach_set("co", co.reshape(-1))
    src.data.update()


def converted_cube(**kw):
    src = helpers.add_primitive("cube")
    assert bpy.ops.object.gbsurf_convert(resolution=3, **kw) == {'FINISHED'}
    return src, bpy.context.active_object


def test_undo_after_convert_restores_the_scene():
    # Headless bpy pushes no undo step after an operator called from Python (the window manager
    # does that in the UI for operators with the UNDO flag), so the test pushes the steps the UI
    # would push: "cube added" before, "GB Surface" after the operator.
    helpers.add_primitive("cube")
    bpy.ops.ed.undo_push(message="cube added")
    before = helpers.snapshot()
    assert bpy.ops.object.gbsurf_convert(resolution=3, want_curves=True) == {'FINISHED'}
    bpy.ops.ed.undo_push(message="GB Surface")
    assert "cube.GB" in bpy.data.objects and "cube.GB.curves" in bpy.data.objects
    bpy.ops.ed.undo()
    assert helpers.snapshot() == before
    bpy.ops.ed.redo()
    assert "cube.GB" in bpy.data.objects


def test_update_regenerates_after_the_source_changes():
    src, out = converted_cube()
    old_extent = np.ptp(coords(out.data), axis=0)
    scale_source(src, 2.0)
    src.location = (5.0, 0.0, 0.0)
    helpers.select_only(out)
    assert bpy.ops.object.gbsurf_update() == {'FINISHED'}
    new_extent = np.ptp(coords(out.data), axis=0)
    assert np.allclose(new_extent, 2.0 * old_extent, rtol=1e-5)
    assert tuple(out.matrix_world.translation) == pytest.approx((5.0, 0.0, 0.0))
    assert out.name == "cube.GB" and out.data.name == "cube.GB"
    assert len([m for m in bpy.data.meshes if m.users == 0]) == 0


def test_update_uses_the_edited_settings():
    src, out = converted_cube()
    n_before = len(out.data.polygons)
    out.gbsurf.resolution = 6
    out.gbsurf.want_curves = True
    helpers.select_only(out)
    assert bpy.ops.object.gbsurf_update() == {'FINISHED'}
    assert len(out.data.polygons) == n_before * 4  # n r^2 triangles per patch
    assert out.gbsurf.curves_object is not None
    out.gbsurf.want_curves = False
    assert bpy.ops.object.gbsurf_update() == {'FINISHED'}
    assert out.gbsurf.curves_object is None and "cube.GB.curves" not in bpy.data.objects


def test_update_error_leaves_the_result_unchanged():
    src, out = converted_cube()
    co = coords(src.data)
    co[0, 0] = np.nan
    src.data.vertices.foreach_set("co", co.reshape(-1))
    src.data.update()
    before = helpers.snapshot()
    helpers.select_only(out)
    with pytest.raises(RuntimeError, match="NaN|not finite"):
        bpy.ops.object.gbsurf_update()
    assert helpers.snapshot() == before


def test_update_without_source():
    src, out = converted_cube()
    bpy.data.objects.remove(src)
    bpy.context.view_layer.update()
    assert out.gbsurf.source is None
    helpers.select_only(out)
    with pytest.raises(RuntimeError, match="source object is gone"):
        bpy.ops.object.gbsurf_update()


def test_live_mode_follows_the_source():
    src, out = converted_cube()
    old_extent = np.ptp(coords(out.data), axis=0)
    out.gbsurf.live = True
    bpy.context.view_layer.update()
    scale_source(src, 3.0)
    bpy.context.view_layer.update()
    assert np.allclose(np.ptp(coords(out.data), axis=0), 3.0 * old_extent, rtol=1e-5)
    # A transform of the source moves the result.
    src.location = (0.0, 4.0, 0.0)
    bpy.context.view_layer.update()
    assert tuple(out.matrix_world.translation) == pytest.approx((0.0, 4.0, 0.0))
    # Settings changes regenerate as well.
    n = len(out.data.polygons)
    out.gbsurf.resolution = 6
    bpy.context.view_layer.update()
    assert len(out.data.polygons) == 4 * n
    # The handler settled: another update changes nothing.
    mesh = out.data
    bpy.context.view_layer.update()
    assert out.data == mesh
    assert not helpers.mesh_module().handlers._busy


def test_live_mode_off_does_not_regenerate():
    src, out = converted_cube()
    mesh = out.data.name
    extent = np.ptp(coords(out.data), axis=0)
    scale_source(src, 2.0)
    bpy.context.view_layer.update()
    assert out.data.name == mesh and np.allclose(np.ptp(coords(out.data), axis=0), extent)


def test_live_mode_is_safe_across_undo():
    src, out = converted_cube()
    out.gbsurf.live = True
    bpy.ops.ed.undo_push(message="live on")
    extent = np.ptp(coords(out.data), axis=0)
    scale_source(src, 2.0)
    bpy.context.view_layer.update()
    bpy.ops.ed.undo_push(message="scaled")
    assert np.allclose(np.ptp(coords(bpy.data.objects["cube.GB"].data), axis=0), 2 * extent, rtol=1e-5)
    bpy.ops.ed.undo()
    bpy.context.view_layer.update()
    out = bpy.data.objects["cube.GB"]  # references are stale after undo
    assert out.gbsurf.live
    assert np.allclose(np.ptp(coords(out.data), axis=0), extent, rtol=1e-5)
    scale_source(bpy.data.objects["cube"], 0.5)
    bpy.context.view_layer.update()
    assert np.allclose(np.ptp(coords(out.data), axis=0), 0.5 * extent, rtol=1e-5)


def test_live_mode_error_is_stored_not_raised():
    src, out = converted_cube()
    out.gbsurf.live = True
    bpy.context.view_layer.update()
    mesh = out.data.name
    co = coords(src.data)
    co[1, 2] = np.inf
    src.data.vertices.foreach_set("co", co.reshape(-1))
    src.data.update()
    bpy.context.view_layer.update()
    assert out.data.name == mesh
    assert out.gbsurf.info.startswith("Live update failed")


def test_display_switches_the_active_colour():
    src, out = converted_cube()
    out.gbsurf.display = 'G1'
    assert out.data.color_attributes.active_color.name == "gb_g1_color"
    out.gbsurf.display = 'PATCH'
    assert out.data.color_attributes.active_color.name == "gb_patch_color"
    mat = out.data.materials[0]
    assert any(n.type == 'VERTEX_COLOR' for n in mat.node_tree.nodes)
