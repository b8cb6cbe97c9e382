"""Every bad model gives an error and leaves the scene unchanged; Blender keeps running."""

import bpy
import numpy as np
import pytest

import helpers

# Bad models a Blender mesh can hold (garbage.obj does not parse, index_out_of_range.obj names a
# missing vertex: both are covered through the batch script and the native tests).
IN_BLENDER = [
    "bowtie_vertex.obj", "duplicate_face.obj", "flipped_face.obj", "huge_coordinates.obj",
    "inf.obj", "nan.obj", "nonmanifold_edge.obj", "repeated_index.obj", "zero_area.obj",
]


def assert_fails_unchanged(match=None):
    before = helpers.snapshot()
    with helpers.refused(match) as e:
        bpy.ops.object.gbsurf_convert(resolution=3)
    assert helpers.snapshot() == before
    return str(e.value)


@pytest.mark.parametrize("model", IN_BLENDER)
def test_bad_model_is_rejected(model):
    src = helpers.load_model(helpers.BAD / model)
    message = assert_fails_unchanged()
    assert src.name in message  # names the object ...
    assert "gbsurf_convert" in message or "no faces" in message  # ... and the library's reason


def test_nan_message_names_the_vertex():
    helpers.load_model(helpers.BAD / "nan.obj")
    assert "vertex 0" in assert_fails_unchanged(match="not finite")


def test_empty_mesh():
    helpers.add_mesh_object("empty", np.zeros((0, 3)), [])
    assert_fails_unchanged(match="no faces")


def test_loose_vertices_only():
    helpers.add_mesh_object("points", np.eye(3), [])
    assert_fails_unchanged(match="no faces")


def test_isolated_vertex_is_accepted_with_a_warning():
    helpers.load_model(helpers.BAD / "isolated_vertex.obj")
    assert bpy.ops.object.gbsurf_convert(resolution=3) == {'FINISHED'}
    assert "isolated_vertex.GB" in bpy.data.objects


def test_no_mesh_selected():
    empty = bpy.data.objects.new("empty", None)
    bpy.context.scene.collection.objects.link(empty)
    helpers.select_only(empty)
    with helpers.refused("poll"):
        bpy.ops.object.gbsurf_convert()


def test_one_bad_object_among_good_ones_converts_the_good_ones(capfd):
    # Multi-object convert: the good objects convert (one operator run: one undo step), each
    # failure is reported as a warning naming the object and the error, plus a summary.
    good = helpers.add_primitive("cube")
    bad = helpers.load_model(helpers.BAD / "nonmanifold_edge.obj")
    helpers.select_only(good, bad)
    assert bpy.ops.object.gbsurf_convert(resolution=3) == {'FINISHED'}
    assert "cube.GB" in bpy.data.objects and "nonmanifold_edge.GB" not in bpy.data.objects
    assert [o.name for o in bpy.context.selected_objects] == ["cube.GB"]
    out = capfd.readouterr()
    text = out.out + out.err
    assert "Not converted: nonmanifold_edge: gbsurf_convert" in text, text
    assert "converted 1 of 2 objects; failed: nonmanifold_edge" in text, text


def test_only_bad_objects_create_nothing_and_name_each():
    a = helpers.load_model(helpers.BAD / "nonmanifold_edge.obj")
    b = helpers.load_model(helpers.BAD / "nan.obj")
    helpers.select_only(a, b)
    message = assert_fails_unchanged()
    assert "nonmanifold_edge" in message and "nan" in message


def test_undo_after_a_partial_convert_removes_it_in_one_step():
    good = helpers.add_primitive("cube")
    other = helpers.add_primitive("torus")
    bad = helpers.load_model(helpers.BAD / "nonmanifold_edge.obj")
    helpers.select_only(good, other, bad)
    bpy.ops.ed.undo_push(message="before")
    before = helpers.snapshot()
    assert bpy.ops.object.gbsurf_convert(resolution=2) == {'FINISHED'}
    bpy.ops.ed.undo_push(message="GB Surface")
    assert {"cube.GB", "torus.GB"} <= set(bpy.data.objects.keys())
    bpy.ops.ed.undo()
    assert helpers.snapshot() == before


def test_only_non_mesh_objects_selected_says_so():
    cam = bpy.data.objects.new("cam", bpy.data.cameras.new("cam"))
    bpy.context.scene.collection.objects.link(cam)
    helpers.select_only(cam)
    with helpers.refused("Only non-mesh objects are selected"):
        bpy.ops.object.gbsurf_convert()


def test_error_through_modifiers_says_the_elements_are_of_the_evaluated_mesh():
    bad = helpers.load_model(helpers.BAD / "nonmanifold_edge.obj")
    plain = assert_fails_unchanged()
    assert "after its modifiers" not in plain
    bad.modifiers.new("weld", 'WELD')  # keeps the non-manifold edge
    message = assert_fails_unchanged()
    assert "element numbers are those of the mesh after its modifiers" in message
    bad.modifiers["weld"].show_viewport = False  # a disabled modifier: the edited mesh's numbers
    assert "after its modifiers" not in assert_fails_unchanged()


def test_circle_without_fill_says_what_to_do():
    bpy.ops.mesh.primitive_circle_add(vertices=8, fill_type='NOTHING')
    assert_fails_unchanged(match=r"no faces: fill it or add faces \(F in Edit Mode\)")


def test_invalid_option_value():
    helpers.add_primitive("cube")
    # Blender clamps the operator properties; the library's own check is reached through
    # convert_object, which takes any value.
    mod = helpers.mesh_module()
    before = helpers.snapshot()
    with pytest.raises(mod.core.ConvertError, match="tile"):
        mod.core.convert_object(bpy.data.objects["cube"], method='TOPOLOGY', tile_depth=1.0)
    assert helpers.snapshot() == before


def test_failed_build_leaves_no_orphan_material(tmp_path):
    # The colour material is created with the first result; a build that fails after that (here:
    # the target collection is linked from a library, so the object cannot go there) must remove it.
    from test_convert import _linked_collection

    col = _linked_collection(tmp_path)
    mod = helpers.mesh_module()
    own = helpers.add_primitive("cube")
    own.name = "own"
    assert mod.core.MATERIAL_NAME not in bpy.data.materials
    before = helpers.snapshot()
    with helpers.refused("collection 'LibCol' is linked"):
        mod.core.convert_object(own, resolution=2, want_curves=True, collection=col)
    assert helpers.snapshot() == before


def test_library_missing_is_reported(monkeypatch, tmp_path):
    helpers.add_primitive("cube")
    monkeypatch.setenv("GBSURF_LIB", str(tmp_path / "libgbsurf.so"))
    assert_fails_unchanged(match="library missing")


def test_catmull_clark_levels_8_on_a_big_cage_is_an_error_not_a_crash():
    # 192 quads at 8 levels would be 12.6 million vertices (~14 GB): the library refuses before
    # any work, Blender keeps running and the scene is unchanged.
    helpers.add_primitive("torus")
    before = helpers.snapshot()
    with helpers.refused("output too large") as e:
        bpy.ops.object.gbsurf_convert(method='CATMULL_CLARK', levels=8)
    message = str(e.value)
    assert "12582912 output vertices" in message and "Memory Limit" in message
    assert helpers.snapshot() == before
    # The limit is a property with the library's default; raising it is what the message says.
    mod = helpers.mesh_module()
    assert mod.native.library_defaults()["max_memory_mb"] == 2048
    with pytest.raises(mod.core.ConvertError, match="above the limit of 1 MiB"):
        mod.core.convert_object(bpy.data.objects["torus"], method='CATMULL_CLARK', levels=1, max_memory_mb=1)
    assert helpers.snapshot() == before
