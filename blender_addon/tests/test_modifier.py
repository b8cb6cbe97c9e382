"""Modifier-like behaviour: undo, Update, live mode, settings kept on the result."""

import bpy
import numpy as np
import pytest
from mathutils import Matrix

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
    with helpers.refused("NaN|not finite"):
        bpy.ops.object.gbsurf_update()
    assert helpers.snapshot() == before


def test_update_without_source():
    src, out = converted_cube()
    bpy.data.objects.remove(src)
    bpy.context.view_layer.update()
    assert out.gbsurf.source is None
    helpers.select_only(out)
    with helpers.refused("source object is gone"):
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
    mesh_io = helpers.mesh_module().mesh_io
    src, out = converted_cube()
    out.gbsurf.display = 'G1'
    assert out.data.color_attributes.active_color.name == "gb_g1_color"
    out.gbsurf.display = 'PATCH'
    assert out.data.color_attributes.active_color.name == "gb_patch_color"
    # Made when first shown, from the per-vertex attribute it maps: one colour per patch.
    patch = mesh_io.get_point_attribute(out.data, "gb_patch")
    rgba = mesh_io.get_point_attribute(out.data, "gb_patch_color")
    assert np.allclose(rgba, mesh_io.index_colors(patch))
    assert len({tuple(c) for c in rgba.round(6)}) > 1
    out.gbsurf.display = 'MEAN_CURVATURE'
    assert out.data.color_attributes.active_color.name == "gb_curvature_color"
    mat = out.data.materials[0]
    assert any(n.type == 'VERTEX_COLOR' for n in mat.node_tree.nodes)


# --- review findings ----------------------------------------------------------------------------

def test_result_keeps_the_source_parent():
    # A parented source: the result gets the same parent relation, so it stays on the source when
    # the parent moves, also with live mode off.
    bpy.ops.object.empty_add(location=(5.0, 0.0, 0.0), rotation=(0.0, 0.0, 0.7))
    parent = bpy.context.active_object
    src = helpers.add_primitive("cube")
    src.parent = parent
    src.location = (0.0, 1.0, 0.0)
    bpy.context.view_layer.update()
    helpers.select_only(src)
    assert bpy.ops.object.gbsurf_convert(resolution=2) == {'FINISHED'}
    out = bpy.data.objects["cube.GB"]
    bpy.context.view_layer.update()
    assert out.parent == parent
    assert np.allclose(np.array(out.matrix_world), np.array(src.matrix_world))
    parent.location = (0.0, 7.0, 1.0)
    bpy.context.view_layer.update()
    assert np.allclose(np.array(out.matrix_world), np.array(src.matrix_world))
    assert tuple(out.matrix_world.translation) != pytest.approx((5.0, 0.0, 0.0), abs=0.5)


def test_source_deleted_in_the_ui_counts_as_gone():
    # object.delete only unlinks an object that our pointer still uses: it must not be used as a
    # source afterwards (Update errors, live mode skips it, the panel says so).
    src, out = converted_cube()
    out.gbsurf.live = True
    bpy.context.view_layer.update()
    helpers.select_only(src)
    assert bpy.ops.object.delete() == {'FINISHED'}
    assert helpers.mesh_module().core.live_source(out) is None
    mesh = out.data.name
    bpy.context.view_layer.update()
    assert out.data.name == mesh
    helpers.select_only(out)
    with helpers.refused("source object is gone"):
        bpy.ops.object.gbsurf_update()


def test_update_keeps_the_users_material():
    src, out = converted_cube()
    mine = bpy.data.materials.new("Mine")
    out.data.materials.clear()
    out.data.materials.append(mine)
    helpers.select_only(out)
    assert bpy.ops.object.gbsurf_update() == {'FINISHED'}
    assert [m.name for m in out.data.materials] == ["Mine"]
    out.gbsurf.live = True
    scale_source(src, 2.0)
    bpy.context.view_layer.update()
    assert [m.name for m in out.data.materials] == ["Mine"]


def test_duplicated_result_leaves_the_originals_extras_alone():
    src, out = converted_cube(want_curves=True)
    curves = out.gbsurf.curves_object
    assert curves is not None
    helpers.select_only(out)
    assert bpy.ops.object.duplicate() == {'FINISHED'}
    copy = bpy.context.active_object
    assert copy != out and copy.gbsurf.curves_object == curves  # the pointer was copied
    copy.gbsurf.want_curves = False
    helpers.select_only(copy)
    assert bpy.ops.object.gbsurf_update() == {'FINISHED'}
    assert "cube.GB.curves" in bpy.data.objects and out.gbsurf.curves_object == curves
    assert curves.parent == out and len(curves.data.splines) == 12


def test_live_mode_after_reloading_the_file(tmp_path):
    src, out = converted_cube()
    out.gbsurf.live = True
    bpy.context.view_layer.update()
    extent = np.ptp(coords(out.data), axis=0)
    path = tmp_path / "live.blend"
    bpy.ops.wm.save_as_mainfile(filepath=str(path))
    bpy.ops.wm.open_mainfile(filepath=str(path))
    out = bpy.data.objects["cube.GB"]
    scale_source(bpy.data.objects["cube"], 2.0)
    bpy.context.view_layer.update()
    assert np.allclose(np.ptp(coords(out.data), axis=0), 2 * extent, rtol=1e-5)


def test_mirror_modifier_of_the_source_is_applied():
    src = helpers.add_primitive("cube")
    scale = coords(src.data) + np.array([3.0, 0.0, 0.0], np.float32)
    src.data.vertices.foreach_set("co", scale.reshape(-1))
    src.data.update()
    src.modifiers.new("mirror", 'MIRROR')
    assert bpy.ops.object.gbsurf_convert(resolution=2) == {'FINISHED'}
    co = coords(bpy.data.objects["cube.GB"].data)
    assert co[:, 0].min() < -3.5 and co[:, 0].max() > 3.5
    assert len(src.data.vertices) == 8  # the source keeps its modifier, unapplied


def test_no_handler_left_after_disabling():
    import addon_utils

    names = ("depsgraph_update_post", "undo_pre", "undo_post", "redo_pre", "redo_post", "load_post",
             "frame_change_post", "save_pre", "render_pre", "render_post", "render_cancel")

    def ours():
        return sum(1 for n in names for f in getattr(bpy.app.handlers, n)
                   if getattr(f, "__module__", "").endswith("gbsurf.handlers"))

    assert ours() == len(names)
    mod = helpers.mesh_module().__name__
    addon_utils.disable(mod, default_set=True)
    assert ours() == 0
    addon_utils.enable(mod, default_set=True)
    assert ours() == len(names)


def test_a_gb_output_is_no_source():
    src, out = converted_cube(want_control_net=True)
    net = out.gbsurf.net_object
    props = helpers.mesh_module().props
    assert props._poll_mesh(out.gbsurf, src)
    assert not props._poll_mesh(out.gbsurf, net) and not props._poll_mesh(out.gbsurf, out)
    out.gbsurf.source = net  # Python skips the poll: Update refuses instead
    before = helpers.snapshot()
    helpers.select_only(out)
    with helpers.refused("is a GB Surface output"):
        bpy.ops.object.gbsurf_update()
    assert helpers.snapshot() == before


def test_redo_replaces_the_previous_result():
    # Adjust Last Operation = undo to the step before the operator, then execute with the new
    # options: the previous result must go with the undo (no piling up of .GB.001 objects).
    helpers.add_primitive("cube")
    bpy.ops.ed.undo_push(message="cube added")
    assert bpy.ops.object.gbsurf_convert(resolution=2, want_curves=True) == {'FINISHED'}
    bpy.ops.ed.undo_push(message="GB Surface")
    bpy.ops.ed.undo()
    assert bpy.ops.object.gbsurf_convert(resolution=3) == {'FINISHED'}
    gb = sorted(o.name for o in bpy.data.objects if o.name.startswith("cube.GB"))
    assert gb == ["cube.GB"] and bpy.data.objects["cube.GB"].gbsurf.resolution == 3
    assert "cube.GB.curves" not in bpy.data.curves


# --- transform kept relative to the source --------------------------------------------------------

def test_update_keeps_the_result_where_the_user_moved_it():
    src, out = converted_cube()
    out.location = (3.0, 0.0, 0.0)  # moved aside by the user
    src.location = (0.0, 4.0, 0.0)
    src.rotation_euler = (0.0, 0.0, 0.5)
    bpy.context.view_layer.update()
    helpers.select_only(out)
    assert bpy.ops.object.gbsurf_update() == {'FINISHED'}
    bpy.context.view_layer.update()
    expected = src.matrix_world @ Matrix.Translation((3.0, 0.0, 0.0))
    assert np.allclose(np.array(out.matrix_world), np.array(expected), atol=1e-5)
    # A second Update with nothing moved changes nothing.
    assert bpy.ops.object.gbsurf_update() == {'FINISHED'}
    bpy.context.view_layer.update()
    assert np.allclose(np.array(out.matrix_world), np.array(expected), atol=1e-5)


def test_live_mode_keeps_the_offset_when_the_source_moves():
    src, out = converted_cube()
    out.gbsurf.live = True
    bpy.context.view_layer.update()
    out.location = (0.0, 0.0, 2.5)
    bpy.context.view_layer.update()
    src.location = (1.0, 0.0, 0.0)
    bpy.context.view_layer.update()
    assert tuple(out.matrix_world.translation) == pytest.approx((1.0, 0.0, 2.5), abs=1e-5)
    scale_source(src, 2.0)  # a regeneration keeps it too
    bpy.context.view_layer.update()
    assert tuple(out.matrix_world.translation) == pytest.approx((1.0, 0.0, 2.5), abs=1e-5)


# --- live mode and animation ----------------------------------------------------------------------

def _displaced_cube():
    src = helpers.add_primitive("cube")
    mod = src.modifiers.new("displace", 'DISPLACE')  # no texture: a push along the normals
    mod.mid_level = 0.0  # by `strength`
    mod.strength = 0.0
    mod.keyframe_insert("strength", frame=1)
    mod.strength = 1.0
    mod.keyframe_insert("strength", frame=10)
    bpy.context.scene.frame_set(1)
    helpers.select_only(src)
    assert bpy.ops.object.gbsurf_convert(resolution=3) == {'FINISHED'}
    return src, bpy.context.active_object


def test_live_mode_follows_an_animated_modifier():
    src, out = _displaced_cube()
    core = helpers.mesh_module().core
    out.gbsurf.live = True
    bpy.context.view_layer.update()
    e1 = np.ptp(coords(out.data), axis=0)
    before = core.conversions
    bpy.context.scene.frame_set(10)
    assert core.conversions == before + 1
    e10 = np.ptp(coords(out.data), axis=0)
    assert np.all(e10 > e1 + 1.0), (e1, e10)  # pushed out by 1 on every side
    bpy.context.scene.frame_set(1)
    assert np.allclose(np.ptp(coords(out.data), axis=0), e1, rtol=1e-5)
    # Without live mode the frame changes nothing.
    out.gbsurf.live = False
    mesh = out.data.name
    bpy.context.scene.frame_set(10)
    assert out.data.name == mesh and np.allclose(np.ptp(coords(out.data), axis=0), e1, rtol=1e-5)


def test_frame_change_without_animation_converts_nothing():
    src, out = converted_cube()
    core = helpers.mesh_module().core
    out.gbsurf.live = True
    bpy.context.view_layer.update()
    before = core.conversions
    mesh = out.data
    for f in (2, 3, 7, 1):
        bpy.context.scene.frame_set(f)
    assert core.conversions == before and out.data == mesh


def test_live_mode_follows_an_animated_source_transform():
    src, out = converted_cube()
    src.location = (0.0, 0.0, 0.0)
    src.keyframe_insert("location", frame=1)
    src.location = (0.0, 6.0, 0.0)
    src.keyframe_insert("location", frame=5)
    bpy.context.scene.frame_set(1)
    out.gbsurf.live = True
    bpy.context.view_layer.update()
    core = helpers.mesh_module().core
    before = core.conversions
    bpy.context.scene.frame_set(5)
    assert tuple(out.matrix_world.translation) == pytest.approx((0.0, 6.0, 0.0), abs=1e-5)
    assert core.conversions == before  # moved, not converted


def test_frame_change_error_is_stored_and_not_retried_every_frame():
    src, out = _displaced_cube()
    core = helpers.mesh_module().core
    out.gbsurf.live = True
    bpy.context.view_layer.update()
    mesh = out.data.name
    # The Displace pushes along vertex normals: a NaN strength makes every position NaN.
    src.animation_data_clear()
    src.modifiers["displace"].strength = float("nan")
    bpy.context.scene.frame_set(3)
    assert out.data.name == mesh and out.gbsurf.info.startswith("Live update failed"), out.gbsurf.info
    before = core.conversions
    for f in (4, 5, 6):
        bpy.context.scene.frame_set(f)
    assert core.conversions == before and out.data.name == mesh


# --- a source deleted in the UI -------------------------------------------------------------------

def test_deleted_source_is_released_on_save(tmp_path):
    src, out = converted_cube()
    n_vertices = len(out.data.vertices)
    helpers.select_only(src)
    assert bpy.ops.object.delete() == {'FINISHED'}
    path = tmp_path / "deleted.blend"
    bpy.ops.wm.save_as_mainfile(filepath=str(path))
    bpy.ops.wm.open_mainfile(filepath=str(path))
    assert "cube" not in bpy.data.objects and "cube" not in bpy.data.meshes
    out = bpy.data.objects["cube.GB"]
    assert out.gbsurf.source is None and len(out.data.vertices) == n_vertices
    assert "Source cube removed" in out.gbsurf.info


def test_a_source_still_in_a_scene_is_kept_on_save(tmp_path):
    src, out = converted_cube()
    path = tmp_path / "kept.blend"
    bpy.ops.wm.save_as_mainfile(filepath=str(path))
    bpy.ops.wm.open_mainfile(filepath=str(path))
    assert bpy.data.objects["cube.GB"].gbsurf.source == bpy.data.objects["cube"]


# --- render resolution ----------------------------------------------------------------------------

def _no_orphan_meshes():
    return [m.name for m in bpy.data.meshes if m.users == 0 or m.use_fake_user]


def test_render_resolution_is_used_for_renders_and_restored():
    src, out = converted_cube()  # resolution 3
    handlers = helpers.mesh_module().handlers
    assert out.gbsurf.render_resolution == 6  # one step finer by default
    n, name = len(out.data.polygons), out.data.name
    for end in (handlers.on_render_post, handlers.on_render_post):  # render_post, render_cancel
        handlers.on_render_pre(bpy.context.scene)
        assert len(out.data.polygons) == 4 * n
        handlers.on_render_pre(bpy.context.scene)  # a second call (next frame) swaps nothing more
        assert len(out.data.polygons) == 4 * n
        end(bpy.context.scene)
        assert out.data.name == name and len(out.data.polygons) == n
        assert _no_orphan_meshes() == []
    assert handlers.on_render_post in bpy.app.handlers.render_cancel
    # Equal resolutions, or a failing source: the viewport mesh renders, nothing raises.
    out.gbsurf.render_resolution = 3
    handlers.on_render_pre(bpy.context.scene)
    assert out.data.name == name
    out.gbsurf.render_resolution = 6
    co = coords(src.data)
    co[0, 0] = np.nan
    src.data.vertices.foreach_set("co", co.reshape(-1))
    src.data.update()
    handlers.on_render_pre(bpy.context.scene)
    assert out.data.name == name
    handlers.on_render_post(bpy.context.scene)
    assert out.data.name == name and _no_orphan_meshes() == []


def test_a_tiny_render_uses_the_render_resolution(tmp_path):
    src, out = converted_cube()
    n, name = len(out.data.polygons), out.data.name
    scene = bpy.context.scene
    seen = []

    def count(scene, *_):
        seen.append(len(bpy.data.objects["cube.GB"].data.polygons))

    cam = bpy.data.objects.new("cam", bpy.data.cameras.new("cam"))
    scene.collection.objects.link(cam)
    cam.location = (0.0, -6.0, 0.0)
    cam.rotation_euler = (1.5708, 0.0, 0.0)
    scene.camera = cam
    scene.render.engine = 'CYCLES'  # CPU, one sample: ~8 s headless (Workbench needs EGL: ~20 s)
    scene.cycles.device = 'CPU'
    scene.cycles.samples = 1
    scene.render.resolution_x = scene.render.resolution_y = 8
    scene.render.filepath = str(tmp_path / "r.png")
    bpy.app.handlers.render_post.insert(0, count)  # before ours restores
    try:
        try:
            bpy.ops.render.render(write_still=True)
        except RuntimeError as e:  # no GPU context headless
            pytest.skip(f"headless render unavailable: {e}")
    finally:
        bpy.app.handlers.render_post.remove(count)
    assert seen == [4 * n]
    assert out.data.name == name and len(out.data.polygons) == n and _no_orphan_meshes() == []
