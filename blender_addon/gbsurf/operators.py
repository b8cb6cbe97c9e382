"""Operators: Convert (`object.gbsurf_convert`) and Update (`object.gbsurf_update`).

Convert run from a script or through Adjust Last Operation (`execute`) works synchronously and
shows progress in the window manager's progress indicator. Started from the UI (`invoke` with a
window) it reads the source meshes, runs the library in a worker thread (the library releases the
GIL and calls back with its progress) and polls with a timer: Esc or right-click cancels through the
progress callback. Blender data is created only on the main thread, after every source was tried:
the objects that converted get their results (one undo step), each one that failed is reported
as a warning naming it, with a summary; when none converted the operator is cancelled with the
error. Cancelling creates nothing.
"""

import threading

import bpy

from . import core, mesh_io
from .props import ConvertOptionsMixin


def _is_source(obj):
    # GB results and their curve / control-net objects are outputs, not control meshes: a
    # "select all, convert" must not convert them again (control nets would even fail).
    return obj is not None and obj.type == 'MESH' and not core.is_result_part(obj)


def _selected_sources(context):
    objs = [o for o in context.selected_objects if _is_source(o)]
    if not objs and _is_source(context.active_object):
        objs = [context.active_object]
    return objs


def _select_only(context, objs):
    for o in context.view_layer.objects:
        if o.select_get():
            o.select_set(False)
    for o in objs:
        try:
            o.select_set(True)
        except RuntimeError:  # not in this view layer
            pass
    if objs:
        context.view_layer.objects.active = objs[-1]


class _Progress:
    """Progress of several conversions in a row, in the window manager's indicator."""

    def __init__(self, wm, count):
        self.wm, self.count, self.index = wm, max(count, 1), 0
        self.cancel = False
        self.fraction = 0.0

    def __call__(self, f):
        self.fraction = (self.index + f) / self.count
        return not self.cancel


class OBJECT_OT_gbsurf_convert(ConvertOptionsMixin, bpy.types.Operator):
    """Convert each selected mesh into a smooth surface of Generalized Bezier patches (a new object <name>.GB)"""

    bl_idname = "object.gbsurf_convert"
    bl_label = "GB Surface"
    bl_options = {'REGISTER', 'UNDO'}

    @classmethod
    def poll(cls, context):
        if context.mode != 'OBJECT':
            cls.poll_message_set("Switch to Object Mode to convert")
            return False
        if not _selected_sources(context):
            if context.selected_objects and not any(o.type == 'MESH' for o in context.selected_objects):
                cls.poll_message_set("Only non-mesh objects are selected: select a mesh object")
            else:
                cls.poll_message_set("Select a mesh object (GB Surface results are not converted again)")
            return False
        return True

    def draw(self, context):
        self.draw_options(self.layout)

    # -- synchronous path ---------------------------------------------------------------------
    def execute(self, context):
        sources = _selected_sources(context)
        if not sources:
            self.report({'ERROR'}, "No mesh object selected")
            return {'CANCELLED'}
        wm = context.window_manager
        progress = _Progress(wm, len(sources))
        wm.progress_begin(0.0, 1.0)
        try:
            depsgraph = context.evaluated_depsgraph_get()
            done, failures = [], []
            for i, src in enumerate(sources):
                progress.index = i

                def cb(f, progress=progress):
                    ok = progress(f)
                    wm.progress_update(progress.fraction)
                    return ok

                try:
                    done.append((src, core.compute(
                        src, self.library_options(), self.output_options(), cb, depsgraph)))
                except core.ConvertError as e:
                    failures.append((src.name, str(e)))
            return self._build(context, done, failures, len(sources))
        finally:
            wm.progress_end()

    def _build(self, context, done, failures, total):
        """Creates the results of `done` [(source, conversion)], all or none; reports each of
        `failures` [(name, message)] and a summary."""
        if not done:
            self.report({'ERROR'}, "; ".join(m for _, m in failures) or "GB Surface: nothing converted")
            return {'CANCELLED'}
        made = []
        try:
            for src, conv in done:
                made.append(core.build_result(src, conv, self.library_options(), self.output_options()))
        except Exception as e:  # creating data failed: remove what this run made
            for obj in made:
                core._remove_ids([x for x in (obj.gbsurf.curves_object, obj.gbsurf.net_object) if x])
                data = obj.data
                bpy.data.objects.remove(obj, do_unlink=True)
                core._remove_orphan(data)
            self.report({'ERROR'}, f"GB Surface: {e}")
            return {'CANCELLED'}
        _select_only(context, made)
        for obj, (_, conv) in zip(made, done):
            for w in conv.warnings:
                self.report({'WARNING'}, f"{obj.name}: {w}")
        for _, message in failures:
            self.report({'WARNING'}, f"Not converted: {message}")
        if failures:
            self.report({'WARNING'}, f"GB Surface: converted {len(made)} of {total} objects; failed: "
                        + ", ".join(name for name, _ in failures))
        else:
            self.report({'INFO'}, "; ".join(f"{o.name}: {o.gbsurf.info}" for o in made))
        return {'FINISHED'}

    # -- interactive path: worker thread + modal timer -----------------------------------------
    def invoke(self, context, event):
        if bpy.app.background or context.window is None:
            return self.execute(context)
        sources = _selected_sources(context)
        if not sources:
            self.report({'ERROR'}, "No mesh object selected")
            return {'CANCELLED'}
        depsgraph = context.evaluated_depsgraph_get()
        readable, data, failures = [], [], []
        for s in sources:
            try:
                data.append(mesh_io.read_object(s, depsgraph))
                readable.append(s)
            except mesh_io.SourceError as e:
                failures.append((s.name, f"{e}{core.evaluated_note(s)}"))
        # The worker touches no Blender data and not the operator (RNA is not thread-safe): it
        # shares only these plain Python objects with the main thread.
        progress = _Progress(context.window_manager, len(readable))
        convs, errors = [], []
        named = [_Named(s.name, core.has_enabled_modifiers(s)) for s in readable]
        options, outputs = self.library_options(), self.output_options()

        def work():
            for i, (n, d) in enumerate(zip(named, data)):
                progress.index = i
                try:
                    convs.append((i, core.compute(n, options, outputs, progress, data=d)))
                except core.ConvertError as e:
                    errors.append((n.name, str(e)))
                except Exception as e:  # reported on the main thread
                    errors.append((n.name, f"GB Surface: {n.name}: {e}"))
                if progress.cancel:
                    return

        self._failures = failures
        self._sources, self._progress, self._convs, self._errors = readable, progress, convs, errors
        self._thread = threading.Thread(target=work, daemon=True)
        wm = context.window_manager
        wm.progress_begin(0.0, 1.0)
        self._timer = wm.event_timer_add(0.1, window=context.window)
        wm.modal_handler_add(self)
        self._thread.start()
        return {'RUNNING_MODAL'}

    def modal(self, context, event):
        wm = context.window_manager
        if event.type in {'ESC', 'RIGHTMOUSE'} and event.value == 'PRESS':
            self._progress.cancel = True
        if event.type != 'TIMER':
            return {'RUNNING_MODAL'}
        wm.progress_update(self._progress.fraction)
        if self._thread.is_alive():
            return {'RUNNING_MODAL'}
        wm.event_timer_remove(self._timer)
        wm.progress_end()
        # The results leave the operator instance here (it may be kept for redo, and each
        # result's arrays keep the library's result alive).
        convs, self._convs = self._convs, []
        if self._progress.cancel:
            self.report({'WARNING'}, "GB Surface: cancelled, nothing created")
            return {'CANCELLED'}
        done = [(self._sources[i], conv) for i, conv in convs]
        failures = self._failures + self._errors
        return self._build(context, done, failures, len(done) + len(failures))


class _Named:
    """A stand-in carrying only a name and whether the source has modifiers (the worker thread
    must not touch bpy objects)."""

    def __init__(self, name, modified=False):
        self.name, self.modified = name, modified


def _results(context):
    objs = [o for o in context.selected_objects if o.gbsurf.is_result]
    a = context.active_object
    if a is not None and a.gbsurf.is_result and a not in objs:
        objs.append(a)
    return objs


class OBJECT_OT_gbsurf_update(bpy.types.Operator):
    """Regenerate the selected GB surfaces from their source meshes and settings"""

    bl_idname = "object.gbsurf_update"
    bl_label = "Update GB Surface"
    bl_options = {'REGISTER', 'UNDO'}

    @classmethod
    def poll(cls, context):
        return bool(_results(context))

    def execute(self, context):
        depsgraph = context.evaluated_depsgraph_get()
        wm = context.window_manager
        wm.progress_begin(0.0, 1.0)
        results = _results(context)
        try:
            convs = [core.compute_for(o, lambda f: wm.progress_update(f) or True, depsgraph)
                     for o in results]
            for obj, conv in zip(results, convs):
                core.apply(obj, conv)
        except core.ConvertError as e:
            self.report({'ERROR'}, str(e))
            return {'CANCELLED'}
        finally:
            wm.progress_end()
        self.report({'INFO'}, f"Updated {len(results)} GB surface(s)")
        return {'FINISHED'}


classes = (OBJECT_OT_gbsurf_convert, OBJECT_OT_gbsurf_update)


def register():
    for c in classes:
        bpy.utils.register_class(c)


def unregister():
    for c in reversed(classes):
        bpy.utils.unregister_class(c)
