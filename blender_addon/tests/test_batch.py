"""blender_addon/batch_convert.py end to end (separate bpy processes) and convert_object."""

import os
import subprocess
import sys
from pathlib import Path

import bpy
import pytest

import helpers
import meshcheck

SCRIPT = helpers.ROOT / "blender_addon" / "batch_convert.py"


def run_batch(args, addon):
    env = dict(os.environ)
    # The source-tree package next to the script, with the library from the installed zip.
    env["GBSURF_LIB"] = str(Path(addon.__file__).parent / "lib" / "libgbsurf.so")
    return subprocess.run([sys.executable, str(SCRIPT), *map(str, args)], env=env,
                          capture_output=True, text=True, timeout=300)


def test_batch_end_to_end(addon, tmp_path):
    # A .blend with two primitives and a .ply written by Blender, plus two shared OBJ models.
    bpy.ops.mesh.primitive_cube_add(location=(3, 0, 0))
    bpy.ops.mesh.primitive_ico_sphere_add(subdivisions=1)
    blend = tmp_path / "scene.blend"
    bpy.ops.wm.save_as_mainfile(filepath=str(blend), copy=True)
    helpers.select_only(bpy.data.objects["Icosphere"])
    ply = tmp_path / "ico.ply"
    bpy.ops.wm.ply_export(filepath=str(ply), export_selected_objects=True, ascii_format=True,
                          export_normals=False, export_uv=False)
    out = tmp_path / "out"
    r = run_batch([helpers.MODELS / "cube.obj", helpers.MODELS / "grid_open.obj", blend, ply,
                   "-o", out, "--method", "TOPOLOGY", "--resolution", "3", "--format", "both"],
                  addon)
    assert r.returncode == 0, r.stdout + r.stderr
    expected = {
        "cube/cube.GB": True, "grid_open/grid_open.GB": False, "scene/Cube.GB": True,
        "scene/Icosphere.GB": True, "ico/ico.GB": True,
    }
    for stem, closed in expected.items():
        for ext in ("obj", "ply"):
            f = out / f"{stem}.{ext}"
            assert f.is_file(), f"{f} missing; stdout: {r.stdout}"
            rep = meshcheck.check_mesh(f)
            assert not rep.problems(expect_closed=closed), (f, rep.problems(expect_closed=closed))
    for stem in ("cube", "grid_open", "scene", "ico"):
        assert (out / f"{stem}.blend").is_file()
    with bpy.data.libraries.load(str(out / "scene.blend")) as (src, _dst):
        names = set(src.objects)
    assert {"Cube", "Cube.GB", "Icosphere", "Icosphere.GB"} <= names


def test_batch_blender_style_arguments(addon, tmp_path):
    # `blender -b --python batch_convert.py -- ARGS`: everything after `--` is ours.
    env = dict(os.environ)
    env["GBSURF_LIB"] = str(Path(addon.__file__).parent / "lib" / "libgbsurf.so")
    r = subprocess.run(
        [sys.executable, str(SCRIPT), "--", str(helpers.MODELS / "pyramid.obj"), "-o",
         str(tmp_path), "--resolution", "2", "--no-blend"],
        env=env, capture_output=True, text=True, timeout=300)
    assert r.returncode == 0, r.stdout + r.stderr
    assert (tmp_path / "pyramid" / "pyramid.GB.obj").is_file()
    assert not (tmp_path / "pyramid.blend").exists()


def test_batch_fails_on_every_bad_model(addon, tmp_path):
    bad = sorted(p for p in helpers.BAD.glob("*.obj") if p.name != "isolated_vertex.obj")
    r = run_batch([*bad, "-o", tmp_path, "--resolution", "2"], addon)
    assert r.returncode == 1, r.stdout + r.stderr
    for p in bad:
        assert str(p) in r.stderr, f"{p.name} not reported:\n{r.stderr}"
    assert not list(tmp_path.rglob("*.GB.obj")), r.stdout


def test_batch_bad_arguments_and_missing_files(addon, tmp_path):
    r = run_batch(["-o"], addon)
    assert r.returncode == 2
    r = run_batch([tmp_path / "missing.obj", "-o", tmp_path], addon)
    assert r.returncode == 1 and "no such file" in r.stderr
    r = run_batch([helpers.MODELS / "cube.obj", "-o", tmp_path, "--method", "NOPE"], addon)
    assert r.returncode == 2


def test_convert_object_from_the_batch_module():
    sys.path.insert(0, str(SCRIPT.parent))
    try:
        import batch_convert
    finally:
        sys.path.remove(str(SCRIPT.parent))
    src = helpers.add_primitive("torus")
    out = batch_convert.convert_object(src, method='DUAL', resolution=2)
    assert out.name == "torus.GB" and out.gbsurf.source == src
    # It is the installed add-on, not a second copy from the source tree.
    assert batch_convert.addon().__name__ == "bl_ext.user_default.gbsurf"


def test_batch_skips_earlier_results_in_a_blend(addon, tmp_path):
    # A .blend saved after a conversion with control nets: only the control mesh is converted
    # again (a control net is not closed and would fail the whole file).
    helpers.add_primitive("cube")
    assert bpy.ops.object.gbsurf_convert(resolution=2, want_control_net=True) == {'FINISHED'}
    blend = tmp_path / "done.blend"
    bpy.ops.wm.save_as_mainfile(filepath=str(blend), copy=True)
    out = tmp_path / "out"
    r = run_batch([blend, "-o", out, "--resolution", "2", "--no-blend"], addon)
    assert r.returncode == 0, r.stdout + r.stderr
    assert sorted(p.name for p in (out / "done").iterdir()) == ["cube.GB.001.obj"]


@pytest.mark.parametrize("flag,value", [("--resolution", "0"), ("--resolution", "100000"),
                                        ("--levels", "-1"), ("--fullness", "1.5")])
def test_batch_refuses_an_option_out_of_range_before_opening_files(addon, tmp_path, flag, value):
    out = tmp_path / "out"
    r = run_batch([tmp_path / "missing.obj", "-o", out, flag, value], addon)
    assert r.returncode == 2, r.stdout + r.stderr
    assert f"{flag} {value}" in r.stderr and "outside the allowed range" in r.stderr, r.stderr
    assert "no such file" not in r.stderr and not out.exists()


def test_batch_converts_every_scene_of_a_blend(addon, tmp_path):
    helpers.add_primitive("cube")
    other = bpy.data.scenes.new("Other")
    mesh = bpy.data.meshes.new("tet")
    mesh.from_pydata([(0, 0, 0), (1, 0, 0), (0, 1, 0), (0, 0, 1)], [],
                     [(0, 2, 1), (0, 1, 3), (0, 3, 2), (1, 2, 3)])
    other.collection.objects.link(bpy.data.objects.new("tet", mesh))
    blend = tmp_path / "two.blend"
    bpy.ops.wm.save_as_mainfile(filepath=str(blend), copy=True)
    out = tmp_path / "out"
    r = run_batch([blend, "-o", out, "--resolution", "2"], addon)
    assert r.returncode == 0, r.stdout + r.stderr
    assert sorted(p.name for p in (out / "two").iterdir()) == ["cube.GB.obj", "tet.GB.obj"]
    assert not meshcheck.check_mesh(out / "two" / "tet.GB.obj").problems(expect_closed=True)
    with bpy.data.libraries.load(str(out / "two.blend")) as (src, _dst):
        assert {"cube.GB", "tet.GB"} <= set(src.objects)
    bpy.ops.wm.open_mainfile(filepath=str(out / "two.blend"))
    assert bpy.data.objects["tet.GB"].users_scene[0].name == "Other"
