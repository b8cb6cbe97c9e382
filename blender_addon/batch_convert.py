"""Batch conversion of meshes into GB surfaces, without the Blender UI.

    python batch_convert.py IN... -o OUTDIR [options]                 (bpy module from PyPI)
    blender -b --python batch_convert.py -- IN... -o OUTDIR [options]  (Blender binary)

Each input (.blend, .obj, .ply) is opened on its own; every mesh object in it is converted
(`<name>.GB`; in a .blend with several scenes, the objects of every scene, each result beside its
source in that scene), each result is written as OUTDIR/<input stem>/<object>.GB.<format> (OBJ and/or
PLY, coordinates in the object's local frame, Z up), and the converted scene as
OUTDIR/<input stem>.blend. The exit status is 0 when every object converted, 1 when any failed
(the failures are listed on stderr), 2 for bad arguments (an option outside the range the add-on
allows, e.g. `--resolution 0`, is refused before any file is opened).

For scripts: `convert_object(obj, **options)` converts one mesh object and returns the new object
(options as in `--help`, e.g. method='TOPOLOGY', resolution=6).

The add-on is used from an installed and enabled extension if there is one (`bl_ext.*.gbsurf`),
else from the `gbsurf` folder next to this script, which finds its native library as described in
gbsurf/native.py (GBSURF_LIB, the bundled lib/, or the checkout's target/release).
"""

import argparse
import math
import os
import sys
import time

import bpy

_addon = None
FLOAT32_MAX = 3.4028234663852886e38


def addon():
    """The gbsurf package, registered (again, if reading factory settings unregistered it)."""
    global _addon
    if _addon is None:
        for name, mod in list(sys.modules.items()):
            if name.startswith("bl_ext.") and name.endswith(".gbsurf") and hasattr(mod, "core"):
                _addon = mod
                break
        else:
            here = os.path.dirname(os.path.abspath(__file__))
            if here not in sys.path:
                sys.path.insert(0, here)
            import gbsurf  # the add-on package next to this script

            _addon = gbsurf
    if not hasattr(bpy.types.Object, "gbsurf"):
        if _addon.__name__.startswith("bl_ext."):
            import addon_utils

            addon_utils.enable(_addon.__name__, default_set=True)
        else:
            _addon.register()
    return _addon


def convert_object(obj, **options):
    """Converts one mesh object into a new object `<name>.GB` beside it and returns it.

    Options: method ('DUAL', 'TOPOLOGY', 'DOO_SABIN', 'CATMULL_CLARK'), resolution, fullness,
    tile_depth, twist ('NONE', 'APPROX', 'INTERP'), mid_scale, middle ('SEED', 'FAIR'), best_plane, weights ('SQUARED',
    'LINEAR'), levels, want_curves, want_control_net, progress (callable(fraction) -> bool).
    Raises the add-on's ConvertError (nothing created then)."""
    return addon().core.convert_object(obj, **options)


def _parser():
    p = argparse.ArgumentParser(prog="batch_convert.py", description=__doc__.split("\n\n")[0])
    p.add_argument("inputs", nargs="+", metavar="IN", help=".blend, .obj or .ply files")
    p.add_argument("-o", "--output", required=True, metavar="OUTDIR")
    p.add_argument("--method", default="DUAL",
                   choices=["DUAL", "TOPOLOGY", "DOO_SABIN", "CATMULL_CLARK"])
    p.add_argument("--resolution", type=int, default=8)
    p.add_argument("--fullness", type=float, default=1.0 / 3.0)
    p.add_argument("--tile-depth", type=float, default=3.0)
    p.add_argument("--twist", default="INTERP", choices=["NONE", "APPROX", "INTERP"])
    p.add_argument("--mid-scale", type=float, default=1.0)
    p.add_argument("--middle", default="SEED", choices=["SEED", "FAIR"])
    p.add_argument("--no-best-plane", action="store_true")
    p.add_argument("--weights", default="SQUARED", choices=["SQUARED", "LINEAR"])
    p.add_argument("--levels", type=int, default=3)
    p.add_argument("--curves", action="store_true", help="also create the curve network objects")
    p.add_argument("--control-net", action="store_true", help="also create the control net objects")
    p.add_argument("--format", default="obj", choices=["obj", "ply", "both"],
                   help="mesh file format of each result (default obj)")
    p.add_argument("--no-blend", action="store_true", help="do not write the .blend files")
    return p


def _arguments(argv):
    if argv is None:
        argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else sys.argv[1:]
    return _parser().parse_args(argv)


def check_ranges(options):
    """Messages for the options outside the range of the add-on's own properties (the one
    definition: props.ConvertOptionsMixin), e.g. resolution 0."""
    props = addon().props
    bad = []
    for name, value in options.items():
        prop = props.ConvertOptionsMixin.__annotations__.get(name)
        kw = getattr(prop, "keywords", {})
        lo, hi = kw.get("min"), kw.get("max")
        if isinstance(value, (int, float)) and not isinstance(value, bool) and (
                (lo is not None and value < lo) or (hi is not None and value > hi)):
            flag = "--" + name.replace("_", "-")
            bounds = f"{lo if lo is not None else '-inf'}..{hi if hi is not None else 'inf'}"
            bad.append(f"{flag} {value} is outside the allowed range {bounds}")
    return bad


def _open(path):
    """Loads one input into a fresh scene; returns [(scene, its mesh objects)] for every scene
    (an object linked into several scenes is listed once, with the first)."""
    ext = os.path.splitext(path)[1].lower()
    if not os.path.isfile(path):
        raise RuntimeError(f"{path}: no such file")
    if ext == ".blend":
        bpy.ops.wm.open_mainfile(filepath=path)
    else:
        bpy.ops.wm.read_factory_settings(use_empty=True)
        addon()  # factory settings may have unregistered an extension-installed add-on
        if ext == ".obj":
            bpy.ops.wm.obj_import(filepath=path, forward_axis='Y', up_axis='Z')
            _check_obj_import(path)
        elif ext == ".ply":
            bpy.ops.wm.ply_import(filepath=path, forward_axis='Y', up_axis='Z')
        else:
            raise RuntimeError(f"{path}: unknown file type {ext!r} (expected .blend, .obj, .ply)")
    # Earlier GB results and their control-net meshes are outputs, not sources.
    core = addon().core
    seen, out = set(), []
    scenes = [bpy.context.scene] + [s for s in bpy.data.scenes if s != bpy.context.scene]
    for scene in scenes:
        objs = [o for o in scene.objects if o.type == 'MESH' and not core.is_result_part(o)
                and o.name not in seen]
        seen.update(o.name for o in objs)
        if objs:
            out.append((scene, objs))
    return out


def _check_obj_import(path):
    """Blender's OBJ importer skips faces it cannot use (bad indices, unparsable lines) and reads
    unusable numbers (nan, inf, beyond float32) with only a log message; a batch job must not
    silently convert something else than the file holds."""
    faces = corners = 0
    with open(path, "r", errors="replace") as f:
        for n, line in enumerate(f, 1):
            parts = line.split()
            if parts and parts[0] == "v":
                try:
                    xyz = [float(x) for x in parts[1:4]]
                except ValueError:
                    raise RuntimeError(f"{path}:{n}: vertex coordinates are not numbers") from None
                if len(xyz) != 3 or not all(math.isfinite(x) and abs(x) <= FLOAT32_MAX for x in xyz):
                    raise RuntimeError(
                        f"{path}:{n}: vertex {' '.join(parts[1:4])} is not three finite numbers "
                        "that fit Blender's 32-bit coordinates")
            if parts and parts[0] == "f":
                faces += 1
                corners += len(parts) - 1
            elif parts and parts[0] not in {"v", "vt", "vn", "vp", "o", "g", "s", "usemtl",
                                             "mtllib", "l", "p", "#", "cstype", "deg", "curv",
                                             "parm", "end"} and not parts[0].startswith("#"):
                raise RuntimeError(f"{path}:{n}: unknown OBJ statement {parts[0]!r}")
    meshes = [o.data for o in bpy.context.scene.objects if o.type == 'MESH']
    got_faces = sum(len(m.polygons) for m in meshes)
    got_corners = sum(len(m.loops) for m in meshes)
    if (got_faces, got_corners) != (faces, corners):
        raise RuntimeError(
            f"{path}: the OBJ importer kept {got_faces} of {faces} faces ({got_corners} of "
            f"{corners} corners): invalid vertex indices or repeated corners")


def _export(obj, path, fmt, scene=None):
    """Writes one object's mesh in its local frame with Blender's exporters (from `scene`, by
    default the context's)."""
    scene = scene or bpy.context.scene
    view_layer = scene.view_layers[0] if scene != bpy.context.scene else bpy.context.view_layer
    with bpy.context.temp_override(scene=scene, view_layer=view_layer):
        _export_selected(obj, path, fmt, view_layer)


def _export_selected(obj, path, fmt, view_layer):
    for o in view_layer.objects:
        o.select_set(False)
    obj.select_set(True)
    view_layer.objects.active = obj
    saved = obj.matrix_world.copy()
    obj.matrix_world.identity()
    try:
        if fmt == "obj":
            bpy.ops.wm.obj_export(
                filepath=path, export_selected_objects=True, forward_axis='Y', up_axis='Z',
                export_materials=False, export_uv=False, apply_modifiers=False)
        else:
            bpy.ops.wm.ply_export(
                filepath=path, export_selected_objects=True, forward_axis='Y', up_axis='Z',
                export_uv=False, export_attributes=True, apply_modifiers=False, ascii_format=False)
    finally:
        obj.matrix_world = saved


def _depsgraph(scene):
    """The evaluated depsgraph of a scene's first view layer (the context's for its scene)."""
    if scene == bpy.context.scene:
        return bpy.context.evaluated_depsgraph_get()
    with bpy.context.temp_override(scene=scene, view_layer=scene.view_layers[0]):
        return bpy.context.evaluated_depsgraph_get()


def _safe(name):
    return "".join(c if c.isalnum() or c in "-_." else "_" for c in name)


def main(argv=None):
    try:
        args = _arguments(argv)
    except SystemExit as e:
        return 2 if e.code else 0
    options = dict(
        method=args.method, resolution=args.resolution, fullness=args.fullness,
        tile_depth=args.tile_depth, twist=args.twist, mid_scale=args.mid_scale, middle=args.middle,
        best_plane=not args.no_best_plane, weights=args.weights, levels=args.levels,
        want_curves=args.curves, want_control_net=args.control_net,
    )
    bad = check_ranges(options)
    if bad:
        for b in bad:
            print(f"error: {b}", file=sys.stderr)
        return 2
    formats = ["obj", "ply"] if args.format == "both" else [args.format]
    os.makedirs(args.output, exist_ok=True)
    core = addon().core
    failures, written = [], []
    for path in args.inputs:
        stem = os.path.splitext(os.path.basename(path))[0]
        try:
            scenes = _open(path)
        except Exception as e:  # unreadable input: report, go on with the others
            failures.append(f"{path}: {e}")
            continue
        if not scenes:
            failures.append(f"{path}: no mesh object")
            continue
        out_dir = os.path.join(args.output, _safe(stem))
        os.makedirs(out_dir, exist_ok=True)
        for scene, sources in scenes:
            depsgraph = _depsgraph(scene)
            for src in sources:
                t0 = time.perf_counter()
                try:
                    result = core.convert_object(src, depsgraph=depsgraph, **options)
                except core.ConvertError as e:
                    failures.append(f"{path}: {e}")
                    continue
                for fmt in formats:
                    target = os.path.join(out_dir, _safe(result.name) + "." + fmt)
                    try:
                        _export(result, target, fmt, scene)
                    except Exception as e:
                        failures.append(f"{path}: scene {scene.name}: {result.name} not written: {e}")
                        continue
                    written.append(target)
                print(f"{path}: {scene.name}: {src.name} -> {result.name}: {result.gbsurf.info} "
                      f"({time.perf_counter() - t0:.2f} s)")
        if not args.no_blend:
            target = os.path.join(args.output, _safe(stem) + ".blend")
            bpy.ops.wm.save_as_mainfile(filepath=os.path.abspath(target), check_existing=False)
            written.append(target)
    for w in written:
        print(f"wrote {w}")
    for f in failures:
        print(f"error: {f}", file=sys.stderr)
    return 1 if failures or not written else 0


if __name__ == "__main__":
    sys.exit(main())
