"""Live mode: a result (or an exact offset surface, `offset_ops`) with `gbsurf.live` regenerates when its source's geometry or transform
changes (and when its own settings change), and on frame changes when the evaluated source
(animated modifiers, shape keys, armatures, drivers, ...) differs from the one last converted:
the frame handler reads the evaluated mesh and compares its digest (`core.source_digest`) with
the one stored on the result, so an unanimated scene costs one mesh read per live result and no
conversion. A moved source carries the result along, keeping the offset the user gave it
(`core.follow_source`).

Before saving, a source that was deleted in the UI (unlinked from every scene, used only by our
pointers) is let go (`on_save_pre`): the pointer is cleared, the result's info says so, and the
object is removed, so the file keeps no invisible data.

The depsgraph handler keeps no reference to Blender data between calls (after undo every
Python reference to an ID is stale): pending work is kept as object *names* and looked up again.
A re-entrancy guard stops the handler from reacting to the updates its own regeneration causes;
nothing is regenerated while undo/redo restores the file. Errors in live mode never raise: they
are stored in the result's `info` and printed.
"""

import bpy
from bpy.app.handlers import persistent

from . import core, mesh_io, offset_ops

_busy = False
_in_undo = False
_pending = set()  # names of result objects whose settings changed


def request_update(obj):
    """Asks for a regeneration of `obj` at the next depsgraph update (settings changed)."""
    if obj is None:
        return
    _pending.add(obj.name)
    # Tag so a depsgraph update (and our handler) follows even without other changes.
    obj.update_tag()


def _live_results():
    return [o for o in bpy.data.objects if core.has_source(o) and o.gbsurf.live]


def _regenerate(obj, depsgraph, data=None):
    """Regenerates a live result or offset surface from its source; `data`: the source's mesh
    already read without vertex groups (frame changes). A failure is stored in the object's info
    (and, with `data`, its digest, so the same frame is not retried), never raised."""
    s = obj.gbsurf
    try:
        if s.is_offset:
            offset_ops.regenerate(obj, depsgraph, data)
        elif data is None:
            core.apply(obj, core.compute_for(obj, None, depsgraph))
        else:
            src = s.source
            # Read again with the vertex groups (one pass over the vertices in Python, skipped
            # for frames whose geometry did not change).
            if len(src.vertex_groups):
                data = mesh_io.read_object(src, depsgraph)
            core.apply(obj, core.compute(src, s.library_options(), s.output_options(), data=data))
    except (core.ConvertError, offset_ops.OffsetError, mesh_io.Float32RangeError) as e:
        s.info = f"Live update failed: {e}"
        if data is not None:
            s.source_digest = core.source_digest(data)
        print(f"gbsurf live: {e}")


@persistent
def on_depsgraph_update(scene, depsgraph):
    global _busy
    if _busy or _in_undo:
        return
    live = _live_results()
    if not live:
        _pending.clear()
        return
    geometry, moved = set(), set()
    for u in depsgraph.updates:
        idb = u.id
        if isinstance(idb, bpy.types.Object):
            name = idb.original.name
            if u.is_updated_geometry:
                geometry.add(name)
            if u.is_updated_transform:
                moved.add(name)
        elif isinstance(idb, bpy.types.Mesh):
            geometry.update(o.name for o in bpy.data.objects if o.data is not None
                            and o.data.name == idb.original.name)
    todo, follow = [], []
    for obj in live:
        src = core.live_source(obj)
        if src is None:  # gone (or deleted in the UI, only held by our pointer)
            continue
        if obj.name in _pending or src.name in geometry:
            todo.append(obj)
        elif src.name in moved:
            follow.append(obj)
    if not todo and not follow:
        return
    _busy = True
    try:
        for obj in follow:
            core.follow_source(obj, obj.gbsurf.source)
        for obj in todo:
            _pending.discard(obj.name)
            try:
                _regenerate(obj, depsgraph)
            except Exception as e:  # a handler must never raise; the other objects still update
                obj.gbsurf.info = f"Live update failed: {e}"
                print(f"gbsurf live: {e}")
    except Exception as e:  # a handler must never raise
        print(f"gbsurf live (depsgraph update): {e}")
    finally:
        _busy = False


@persistent
def on_frame_change(scene, depsgraph=None):
    """Regenerates the live results whose evaluated source changed with the frame; follows moved
    sources. Never raises."""
    global _busy
    if _busy or _in_undo:
        return
    _busy = True
    try:
        if depsgraph is None:
            depsgraph = bpy.context.evaluated_depsgraph_get()
        for obj in _live_results():
            src = core.live_source(obj)
            if src is None or core.is_result_part(src):
                continue
            try:
                data = mesh_io.read_object(src, depsgraph, vertex_groups=False)
            except mesh_io.SourceError as e:
                obj.gbsurf.info = f"Live update failed: {e}"
                continue
            core.follow_source(obj, src)
            if core.source_digest(data) == obj.gbsurf.source_digest:
                continue
            _regenerate(obj, depsgraph, data)
    except Exception as e:  # a handler must never raise
        print(f"gbsurf live (frame change): {e}")
    finally:
        _busy = False


def release_deleted_sources():
    """Clears the source pointers to objects deleted in the UI (in no collection, no fake user,
    no user but our pointers), notes it in the results' info and removes the object (and its
    mesh if nothing else uses it). Returns the names released."""
    pointers = {}
    for o in bpy.data.objects:
        s = o.gbsurf
        if core.has_source(o) and s.source is not None:
            pointers.setdefault(s.source.name, []).append(o)
    released = []
    for name, results in pointers.items():
        src = bpy.data.objects.get(name)
        if (src is None or src.library is not None or src.users_collection or src.use_fake_user
                or src.users > len(results) or src.children):
            continue
        for r in results:
            r.gbsurf.live = False
            r.gbsurf.source = None
            r.gbsurf.info = f"Source {name} removed (deleted from the scene); the surface stays as it is"
        data = src.data
        if src.users == 0:
            bpy.data.objects.remove(src)
            if isinstance(data, bpy.types.Mesh) and data.users == 0:
                bpy.data.meshes.remove(data)
        released.append(name)
    return released


# --- render resolution ---------------------------------------------------------------------------
# Final renders use `render_resolution`: render_pre swaps each such result's mesh for one made at
# that resolution (the viewport mesh is kept with a fake user), render_post / render_cancel swap
# it back and remove the render mesh. Results are kept by name (no ID references across calls).
_render_swaps = {}  # result name -> viewport mesh name


def _wants_render_mesh(obj):
    s = obj.gbsurf
    return (s.is_result and s.method in {'DUAL', 'TOPOLOGY'} and s.render_resolution > 0
            and s.render_resolution != s.resolution and not obj.hide_render
            and obj.type == 'MESH' and core.live_source(obj) is not None)


def render_begin(scene):
    """Swaps in render-resolution meshes for the results of `scene`; returns their names."""
    done = []
    for obj in scene.objects:
        if obj.name in _render_swaps or not _wants_render_mesh(obj):
            continue
        s = obj.gbsurf
        try:
            conv = core.compute(s.source, {**s.library_options(), "resolution": s.render_resolution},
                                {"want_curves": False, "want_control_net": False})
            viewport = obj.data
            mesh = bpy.data.meshes.new(viewport.name + ".render")
            try:
                core.fill_surface(mesh, conv, s.display,
                                  materials=[m for m in viewport.materials if m is not None])
            except Exception:
                bpy.data.meshes.remove(mesh)
                raise
            viewport.use_fake_user = True
            obj.data = mesh
            _render_swaps[obj.name] = viewport.name
            done.append(obj.name)
        except Exception as e:  # the viewport mesh renders instead
            print(f"gbsurf render resolution: {obj.name}: {e}")
    return done


def render_end(*_args):
    """Restores the viewport meshes swapped by `render_begin` (also after a cancelled render)."""
    for name, mesh_name in list(_render_swaps.items()):
        _render_swaps.pop(name, None)
        try:
            obj, viewport = bpy.data.objects.get(name), bpy.data.meshes.get(mesh_name)
            if viewport is None:
                continue
            viewport.use_fake_user = False
            if obj is None:
                continue
            render_mesh = obj.data
            obj.data = viewport
            if render_mesh is not None and render_mesh != viewport and render_mesh.users == 0:
                bpy.data.meshes.remove(render_mesh)
        except Exception as e:
            print(f"gbsurf render resolution: {name}: {e}")


@persistent
def on_render_pre(scene, *_args):
    global _busy
    if _busy:
        return
    _busy = True
    try:
        render_begin(scene)
    except Exception as e:  # a handler must never raise
        print(f"gbsurf (render): {e}")
    finally:
        _busy = False


@persistent
def on_render_post(*_args):
    global _busy
    _busy = True
    try:
        render_end()
    except Exception as e:
        print(f"gbsurf (render): {e}")
    finally:
        _busy = False


@persistent
def on_save_pre(*_args):
    try:
        release_deleted_sources()
    except Exception as e:  # a handler must never raise
        print(f"gbsurf (save): {e}")


@persistent
def on_undo_pre(*_args):
    global _in_undo
    _in_undo = True


@persistent
def on_undo_post(*_args):
    global _in_undo
    _in_undo = False
    _pending.clear()


@persistent
def on_load_post(*_args):
    _pending.clear()
    _render_swaps.clear()


_HANDLERS = (
    ("depsgraph_update_post", on_depsgraph_update),
    ("undo_pre", on_undo_pre),
    ("undo_post", on_undo_post),
    ("redo_pre", on_undo_pre),
    ("redo_post", on_undo_post),
    ("load_post", on_load_post),
    ("frame_change_post", on_frame_change),
    ("save_pre", on_save_pre),
    ("render_pre", on_render_pre),
    ("render_post", on_render_post),
    ("render_cancel", on_render_post),
)


def register():
    for name, fn in _HANDLERS:
        getattr(bpy.app.handlers, name).append(fn)


def unregister():
    for name, fn in _HANDLERS:
        lst = getattr(bpy.app.handlers, name)
        if fn in lst:
            lst.remove(fn)
