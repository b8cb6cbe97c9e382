"""Live mode: a result with `gbsurf.live` regenerates when its source's geometry or transform
changes (and when its own settings change).

The depsgraph handler keeps no reference to Blender data between calls (after undo every
Python reference to an ID is stale): pending work is kept as object *names* and looked up again.
A re-entrancy guard stops the handler from reacting to the updates its own regeneration causes;
nothing is regenerated while undo/redo restores the file. Errors in live mode never raise: they
are stored in the result's `info` and printed.
"""

import bpy
from bpy.app.handlers import persistent

from . import core

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
    return [o for o in bpy.data.objects if o.gbsurf.is_result and o.gbsurf.live]


def _regenerate(obj, depsgraph):
    try:
        core.apply(obj, core.compute_for(obj, None, depsgraph))
    except core.ConvertError as e:
        obj.gbsurf.info = f"Live update failed: {e}"
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
            obj.matrix_world = obj.gbsurf.source.matrix_world.copy()
        for obj in todo:
            _pending.discard(obj.name)
            _regenerate(obj, depsgraph)
    finally:
        _busy = False


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


_HANDLERS = (
    ("depsgraph_update_post", on_depsgraph_update),
    ("undo_pre", on_undo_pre),
    ("undo_post", on_undo_post),
    ("redo_pre", on_undo_pre),
    ("redo_post", on_undo_post),
    ("load_post", on_load_post),
)


def register():
    for name, fn in _HANDLERS:
        getattr(bpy.app.handlers, name).append(fn)


def unregister():
    for name, fn in _HANDLERS:
        lst = getattr(bpy.app.handlers, name)
        if fn in lst:
            lst.remove(fn)
