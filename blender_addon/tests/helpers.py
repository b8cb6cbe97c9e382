"""Shared helpers of the add-on tests (scene building, snapshots, mesh arrays)."""

import contextlib
from pathlib import Path

import bpy
import numpy as np
import pytest

ROOT = Path(__file__).resolve().parents[2]
MODELS = (ROOT / ".." / "shared" / "models").resolve()
BAD = MODELS / "bad"


def mesh_module():
    import sys

    return sys.modules["bl_ext.user_default.gbsurf"]


def parse_obj(path):
    """(positions (V,3), faces list) of an OBJ file: `v` and `f` lines only, 1-based or negative
    indices, `a/b/c` corners. No validation (bad models stay bad)."""
    pos, faces = [], []
    for line in Path(path).read_text().splitlines():
        parts = line.split()
        if not parts:
            continue
        if parts[0] == "v":
            pos.append([float(x) for x in parts[1:4]])
        elif parts[0] == "f":
            idx = [int(c.split("/")[0]) for c in parts[1:]]
            faces.append([i - 1 if i > 0 else len(pos) + i for i in idx])
    return np.array(pos, dtype=np.float64).reshape(-1, 3), faces


def add_mesh_object(name, positions, faces):
    """A mesh object linked to the scene, selected, active. Built with Blender's own
    `from_pydata`, not the add-on's writer: a source mesh may hold what the add-on refuses to
    write (inf, coordinates beyond float32), exactly as a user's mesh can."""
    mesh = bpy.data.meshes.new(name)
    mesh.from_pydata(np.asarray(positions, dtype=np.float64).reshape(-1, 3).tolist(), [], [list(f) for f in faces])
    mesh.update()
    obj = bpy.data.objects.new(name, mesh)
    bpy.context.scene.collection.objects.link(obj)
    select_only(obj)
    return obj


def load_model(path):
    pos, faces = parse_obj(path)
    return add_mesh_object(Path(path).stem, pos, faces)


def select_only(*objs):
    for o in bpy.context.view_layer.objects:
        o.select_set(False)
    for o in objs:
        o.select_set(True)
    bpy.context.view_layer.objects.active = objs[-1] if objs else None


PRIMITIVES = {
    "cube": lambda: bpy.ops.mesh.primitive_cube_add(),
    "uv_sphere": lambda: bpy.ops.mesh.primitive_uv_sphere_add(segments=16, ring_count=8),
    "ico_sphere": lambda: bpy.ops.mesh.primitive_ico_sphere_add(subdivisions=2),
    "cylinder": lambda: bpy.ops.mesh.primitive_cylinder_add(vertices=32),
    "torus": lambda: bpy.ops.mesh.primitive_torus_add(major_segments=24, minor_segments=8),
    "cone": lambda: bpy.ops.mesh.primitive_cone_add(vertices=32),
    "suzanne": lambda: bpy.ops.mesh.primitive_monkey_add(),
}


def add_primitive(name):
    PRIMITIVES[name]()
    obj = bpy.context.active_object
    obj.name = name
    return obj


def mesh_arrays(mesh):
    """(positions (V,3) float64, triangles (T,3)) of a mesh (loop triangles: for checks only)."""
    co = np.empty(len(mesh.vertices) * 3, dtype=np.float32)
    mesh.vertices.foreach_get("co", co)
    mesh.calc_loop_triangles()
    tris = np.empty(len(mesh.loop_triangles) * 3, dtype=np.int32)
    mesh.loop_triangles.foreach_get("vertices", tris)
    return co.reshape(-1, 3).astype(np.float64), tris.reshape(-1, 3)


def has_boundary(mesh):
    """True if some edge of the mesh has a single face."""
    m = mesh_module().mesh_io
    _, sizes, idx = m.read_mesh(mesh)
    starts = np.concatenate(([0], np.cumsum(sizes)[:-1]))
    nxt = np.arange(len(idx)) + 1
    ends = np.repeat(starts + sizes, sizes)
    nxt[nxt == ends] = np.repeat(starts, sizes)[nxt == ends]
    a, b = idx, idx[nxt]
    e = np.sort(np.stack([a, b], axis=1), axis=1)
    _, counts = np.unique(e, axis=0, return_counts=True)
    return bool((counts == 1).any())


def snapshot():
    """A comparable description of the file's data: objects with transforms and mesh arrays."""
    objs = {}
    for o in bpy.data.objects:
        entry = {"type": o.type, "matrix": [tuple(r) for r in o.matrix_world],
                 "data": o.data.name if o.data else None}
        if o.type == 'MESH':
            co = np.empty(len(o.data.vertices) * 3, dtype=np.float32)
            o.data.vertices.foreach_get("co", co)
            entry["co"] = co.tobytes()
            entry["faces"] = len(o.data.polygons)
        objs[o.name] = entry
    return {
        "objects": objs,
        "meshes": sorted(m.name for m in bpy.data.meshes),
        "curves": sorted(c.name for c in bpy.data.curves),
        # Orphan data-blocks count too: every ID collection a conversion could add to.
        "materials": sorted(m.name for m in bpy.data.materials),
        "collections": sorted(c.name for c in bpy.data.collections),
        "counts": {k: len(getattr(bpy.data, k)) for k in (
            "objects", "meshes", "curves", "materials", "collections", "node_groups", "images")},
    }


def subsurf_arrays(obj, levels):
    """Positions and triangles of Blender's own Subdivision Surface (Catmull-Clark) of `obj`."""
    mod = obj.modifiers.new("ref_subsurf", 'SUBSURF')
    mod.levels = levels
    mod.render_levels = levels
    try:
        dg = bpy.context.evaluated_depsgraph_get()
        ev = obj.evaluated_get(dg)
        mesh = ev.to_mesh()
        try:
            return mesh_arrays(mesh)
        finally:
            ev.to_mesh_clear()
    finally:
        obj.modifiers.remove(mod)


@contextlib.contextmanager
def refused(match):
    """`pytest.raises(RuntimeError, match=match)` for an operator call that must be refused with a
    report. A Python exception escaping an operator also reaches the caller as a RuntimeError
    (with the traceback as its message), so this also fails when the message holds one."""
    with pytest.raises(RuntimeError, match=match) as err:
        yield err
    assert "Traceback" not in str(err.value), str(err.value)
