"""The add-on installs from its built zip, registers, and its UI draws."""

import os
import zipfile
from pathlib import Path

import bpy

import helpers


def test_zip_contents(addon_zip):
    assert addon_zip.name.startswith("gbsurf")
    names = set(zipfile.ZipFile(addon_zip).namelist())
    for f in ("blender_manifest.toml", "__init__.py", "operators.py", "props.py", "ui.py",
              "native.py", "mesh_io.py", "handlers.py", "core.py", "lib/libgbsurf.so"):
        assert f in names, f"{f} missing from {addon_zip.name}: {sorted(names)}"
    assert not any("tests/" in n or "__pycache__" in n for n in names)


def test_installed_from_zip_not_source(addon):
    user = Path(os.environ["BLENDER_USER_RESOURCES"]).resolve()
    here = Path(addon.__file__).resolve()
    assert here.is_relative_to(user), f"{here} is not inside the user extensions ({user})"
    assert (here.parent / "lib" / "libgbsurf.so").is_file()
    # The loader picks the bundled library.
    addon.native.load()
    assert Path(addon.native.library_path()).resolve() == (here.parent / "lib" / "libgbsurf.so").resolve()
    assert addon.native.version()


def test_registration():
    assert hasattr(bpy.types.Object, "gbsurf")
    op = bpy.ops.object.gbsurf_convert.get_rna_type()
    assert {'REGISTER', 'UNDO'} <= set(
        helpers.mesh_module().operators.OBJECT_OT_gbsurf_convert.bl_options)
    props = {p.identifier for p in op.properties}
    for name in ("method", "resolution", "fullness", "tile_depth", "twist", "mid_scale",
                 "middle", "best_plane", "weights", "levels", "want_curves", "want_control_net"):
        assert name in props
    items = [i.identifier for i in op.properties["method"].enum_items]
    assert items == ['DUAL', 'TOPOLOGY', 'DOO_SABIN', 'CATMULL_CLARK']
    # (`idname()` answers for any name; `get_rna_type()` fails for an unregistered operator.)
    assert bpy.ops.object.gbsurf_update.get_rna_type().identifier == "OBJECT_OT_gbsurf_update"
    assert hasattr(bpy.types, "OBJECT_PT_gbsurf")
    draw_funcs = bpy.types.VIEW3D_MT_object_convert._dyn_ui_initialize()
    assert any(getattr(f, "__module__", "").endswith("gbsurf.ui") for f in draw_funcs)


class RecordingLayout:
    """Stands in for bpy.types.UILayout in draw() calls (there is no region headless). Every
    `prop` and `operator` call is checked against RNA: a misspelt property or operator fails."""

    def __init__(self, log):
        self.log = log
        self.use_property_split = self.use_property_decorate = False
        self.active = self.enabled = True

    def _child(self, *a, **k):
        return RecordingLayout(self.log)

    column = row = box = split = _child

    def prop(self, data, name, **kw):
        assert name in data.bl_rna.properties, f"no property {name!r} on {data}"
        self.log.append(("prop", name))

    def operator(self, idname, **kw):
        mod, op = idname.split(".")
        assert hasattr(getattr(bpy.ops, mod), op)
        getattr(getattr(bpy.ops, mod), op).get_rna_type()
        self.log.append(("operator", idname))

    def label(self, **kw):
        self.log.append(("label", kw.get("text", "")))


class _Self:
    def __init__(self, layout):
        self.layout = layout


def test_panel_and_menu_draw():
    mod = helpers.mesh_module()
    obj = helpers.add_primitive("cube")
    obj.gbsurf.is_result = True
    obj.gbsurf.source = None
    log = []
    mod.ui.OBJECT_PT_gbsurf.draw(_Self(RecordingLayout(log)), bpy.context)
    assert ("operator", "object.gbsurf_update") in log
    assert ("prop", "live") in log and ("prop", "source") in log and ("prop", "resolution") in log
    assert ("label", "The source object is gone") in log
    log.clear()
    obj.gbsurf.method = 'CATMULL_CLARK'
    mod.ui.OBJECT_PT_gbsurf.draw(_Self(RecordingLayout(log)), bpy.context)
    assert ("prop", "levels") in log and ("prop", "resolution") not in log
    log.clear()
    mod.ui.menu_convert(_Self(RecordingLayout(log)), bpy.context)
    assert log == [("operator", "object.gbsurf_convert"), ("operator", "object.gbsurf_offset"),
                   ("operator", "curve.gbsurf_ph_offset")]
    # The offset settings panel (in ui.py with the other panel) shows only on offset objects.
    assert not mod.ui.OBJECT_PT_gbsurf_offset.poll(bpy.context)
    obj.gbsurf.is_offset = True
    assert mod.ui.OBJECT_PT_gbsurf_offset.poll(bpy.context)
    log.clear()
    mod.ui.OBJECT_PT_gbsurf_offset.draw(_Self(RecordingLayout(log)), bpy.context)
    assert ("operator", "object.gbsurf_offset_update") in log and ("prop", "offset_distance") in log
    obj.gbsurf.is_offset = False
    # The operator's redo panel (Adjust Last Operation) draws the same options.
    log.clear()
    mod.props.ConvertOptionsMixin.draw_options(obj.gbsurf, RecordingLayout(log))
    assert ("prop", "method") in log


def test_panel_poll_only_on_results():
    mod = helpers.mesh_module()
    obj = helpers.add_primitive("cube")
    assert not mod.ui.OBJECT_PT_gbsurf.poll(bpy.context)
    obj.gbsurf.is_result = True
    assert mod.ui.OBJECT_PT_gbsurf.poll(bpy.context)


def test_unregister_and_register_again():
    import addon_utils

    addon_utils.disable(helpers.mesh_module().__name__, default_set=True)
    assert not hasattr(bpy.types.Object, "gbsurf")
    assert not hasattr(bpy.types, "OBJECT_PT_gbsurf")
    addon_utils.enable("bl_ext.user_default.gbsurf", default_set=True)
    assert hasattr(bpy.types.Object, "gbsurf")
