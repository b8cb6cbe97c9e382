"""Renders the demo picture: a model converted by the add-on, coloured by mean curvature, next to
Blender's own Subdivision Surface of the same mesh (Cycles on the CPU).

    .venv/bin/python blender_addon/render_demo.py --zip dist/gbsurf-0.1.0.zip \
        [--model ../shared/models/torus.obj] [-o out/demo/blender.png] [--samples 16]

The add-on is installed from the zip into a temporary user folder (BLENDER_USER_RESOURCES is set
to one when unset), so the picture shows what the packaged extension does. Besides the PNG,
out/demo/blender.blend keeps the scene.
"""

import argparse
import os
import sys
import tempfile
import time

if not os.environ.get("BLENDER_USER_RESOURCES"):
    os.environ["BLENDER_USER_RESOURCES"] = tempfile.mkdtemp(prefix="gbsurf-demo-")

import bpy  # noqa: E402
from mathutils import Vector  # noqa: E402

HERE = os.path.dirname(os.path.abspath(__file__))
DEFAULT_MODEL = os.path.normpath(os.path.join(HERE, "..", "..", "shared", "models", "torus.obj"))


def parse(argv):
    p = argparse.ArgumentParser(prog="render_demo.py")
    p.add_argument("--zip", required=True, help="the built extension zip (scripts/build-addon)")
    p.add_argument("--model", default=DEFAULT_MODEL)
    p.add_argument("-o", "--output", default="out/demo/blender.png")
    p.add_argument("--method", default="DUAL")
    p.add_argument("--resolution", type=int, default=10)
    p.add_argument("--levels", type=int, default=3, help="Subdivision Surface levels")
    p.add_argument("--samples", type=int, default=16)
    p.add_argument("--size", default="1200x600")
    return p.parse_args(argv)


def apply_crease_tags(mesh, path):
    """OpenSubdiv's `t crease 2/1/0 a b s` lines (0-based vertices) as the `crease_edge`
    attribute, c = sqrt(min(s, 10)/10) (Subdivision Surface reads c as sharpness 10·c², like the
    add-on): Blender's OBJ importer drops these tags, and both sides of the picture read them."""
    import numpy as np
    tags = []
    with open(path, encoding="utf-8", errors="replace") as f:
        for line in f:
            w = line.split()
            if len(w) >= 6 and w[0] == "t" and w[1] == "crease":
                tags.append((int(w[3]), int(w[4]), float(w[5])))
    if not tags:
        return
    ev = np.empty(2 * len(mesh.edges), dtype=np.int64)
    mesh.edges.foreach_get("vertices", ev)
    ev = np.sort(ev.reshape(-1, 2), axis=1)
    index = {(int(a), int(b)): i for i, (a, b) in enumerate(ev)}
    crease = np.zeros(len(mesh.edges), dtype=np.float32)
    for a, b, s in tags:
        i = index.get((min(a, b), max(a, b)))
        if i is not None:
            crease[i] = (min(s, 10.0) / 10.0) ** 0.5
    attr = mesh.attributes.get("crease_edge") or mesh.attributes.new("crease_edge", 'FLOAT', 'EDGE')
    attr.data.foreach_set("value", crease)


def grey_material():
    mat = bpy.data.materials.new("Subdivision grey")
    if bpy.app.version < (5, 0, 0):
        mat.use_nodes = True
    bsdf = next(n for n in mat.node_tree.nodes if n.type == 'BSDF_PRINCIPLED')
    bsdf.inputs["Base Color"].default_value = (0.7, 0.7, 0.72, 1.0)
    bsdf.inputs["Roughness"].default_value = 0.4
    return mat


def stamp_note(scene, text):
    """Writes `text` into the picture (render stamp with only the note)."""
    r = scene.render
    for name in dir(r):
        if name.startswith("use_stamp_") and name not in {"use_stamp_note", "use_stamp_labels"}:
            try:
                setattr(r, name, False)
            except (AttributeError, TypeError):
                pass
    r.use_stamp = True
    r.use_stamp_note = True
    r.stamp_note_text = text
    r.stamp_font_size = 20
    r.stamp_foreground = (1.0, 1.0, 1.0, 1.0)
    r.stamp_background = (0.0, 0.0, 0.0, 0.55)


def main(argv):
    a = parse(argv)
    bpy.ops.wm.read_factory_settings(use_empty=True)
    assert bpy.ops.extensions.package_install_files(
        filepath=os.path.abspath(a.zip), repo="user_default", enable_on_install=True) == {'FINISHED'}
    bpy.ops.wm.obj_import(filepath=a.model, forward_axis='Y', up_axis='Z')
    src = next(o for o in bpy.context.scene.objects if o.type == 'MESH')
    apply_crease_tags(src.data, a.model)
    for o in bpy.context.view_layer.objects:
        o.select_set(o == src)
    bpy.context.view_layer.objects.active = src
    t0 = time.perf_counter()
    assert bpy.ops.object.gbsurf_convert(method=a.method, resolution=a.resolution) == {'FINISHED'}
    seconds = time.perf_counter() - t0
    gb = bpy.context.active_object
    gb.gbsurf.display = 'MEAN_CURVATURE'

    ref = src.copy()
    ref.data = src.data.copy()
    ref.name = src.name + ".subsurf"
    bpy.context.scene.collection.objects.link(ref)
    mod = ref.modifiers.new("Subdivision", 'SUBSURF')
    mod.levels = mod.render_levels = a.levels
    ref.data.shade_smooth()
    ref.data.materials.clear()
    ref.data.materials.append(grey_material())
    src.hide_render = True
    src.hide_set(True)

    # Side by side along x, centred on the origin.
    lo = Vector(min(v.co[i] for v in src.data.vertices) for i in range(3))
    hi = Vector(max(v.co[i] for v in src.data.vertices) for i in range(3))
    size = hi - lo
    centre = (lo + hi) / 2
    gap = 0.65 * max(size.x, size.y, size.z)
    offset = size.x / 2 + gap / 2
    gb.matrix_world.identity()
    gb.location = -centre + Vector((-offset, 0, 0))
    ref.location = -centre + Vector((offset, 0, 0))
    extent = max(2 * offset + size.x, size.z * 2.2, size.y)
    scene = bpy.context.scene
    cam = bpy.data.objects.new("Camera", bpy.data.cameras.new("Camera"))
    scene.collection.objects.link(cam)
    scene.camera = cam
    cam.data.lens = 50
    cam.location = Vector((0.0, -1.25 * extent, 0.75 * extent))
    cam.rotation_euler = (Vector((0, 0, 0)) - cam.location).to_track_quat('-Z', 'Y').to_euler()
    sun = bpy.data.objects.new("Sun", bpy.data.lights.new("Sun", 'SUN'))
    sun.data.energy = 3.0
    sun.rotation_euler = (0.7, 0.2, 0.6)
    scene.collection.objects.link(sun)
    world = bpy.data.worlds.new("World")
    if bpy.app.version < (5, 0, 0):
        world.use_nodes = True
    world.node_tree.nodes["Background"].inputs["Color"].default_value = (0.9, 0.9, 0.92, 1.0)
    world.node_tree.nodes["Background"].inputs["Strength"].default_value = 0.8
    scene.world = world

    scene.render.engine = 'CYCLES'
    scene.cycles.device = 'CPU'
    scene.cycles.samples = a.samples
    try:
        scene.cycles.use_denoising = True
    except (AttributeError, TypeError):
        pass
    w, h = (int(x) for x in a.size.split("x"))
    scene.render.resolution_x, scene.render.resolution_y = w, h
    scene.render.resolution_percentage = 100
    scene.render.image_settings.file_format = 'PNG'
    # One line at the default 1200 px width: the stamp wraps longer notes.
    stamp_note(scene, f"left: GB surface ({a.method.lower()}, r={a.resolution}), H: convex red, "
               f"concave blue   right: Subsurf level {a.levels}")
    out = os.path.abspath(a.output)
    os.makedirs(os.path.dirname(out), exist_ok=True)
    scene.render.filepath = out
    t1 = time.perf_counter()
    bpy.ops.render.render(write_still=True)
    print(f"render_demo: {os.path.basename(a.model)} -> {gb.name}: {gb.gbsurf.info} "
          f"(convert {seconds:.2f} s, render {time.perf_counter() - t1:.1f} s)")
    bpy.ops.wm.save_as_mainfile(filepath=os.path.splitext(out)[0] + ".blend", copy=True)
    print(f"render_demo: wrote {out}")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else sys.argv[1:]))
