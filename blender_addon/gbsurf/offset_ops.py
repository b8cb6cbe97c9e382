"""Exact offsets: `Object > Convert > GB Offset Surface` (`object.gbsurf_offset`, the offset of
the GB surface of a mesh through PN pieces; `object.gbsurf_offset_update` regenerates it from its
stored settings, and live mode (handlers.py) through the same `regenerate`) and `Exact Offset (PH)`
in `Object > Convert`, the edit-mode `Curve` menu and the curve context menus
(`curve.gbsurf_ph_offset`, a planar PH quintic spline through a Bezier curve's points and handle
tangents, as an exact order-6 NURBS curve, plus its exact rational offset sampled as a POLY curve).

Everything is computed before any Blender data is created; the sources are never modified.
"""

import json

import bpy
import numpy as np
from bpy.props import FloatProperty, IntProperty

from . import core, mesh_io, native, offset_native
from .props import OffsetOptionsMixin

PATCH_METHODS = {'DUAL', 'TOPOLOGY'}
# A gap larger than this times the output's bounding-box diagonal is warned about.
GAP_WARN = 1e-9
# Custom property holding the exact rational offset of a PH offset curve (a JSON string).
PH_OFFSET_PROPERTY = "gbsurf_ph_offset"
# NURBS order of a quintic (Blender's largest order is 6).
QUINTIC_ORDER = 6


class OffsetError(Exception):
    """An offset failed; the message is ready for `Operator.report`."""


# --- GB offset surface ---------------------------------------------------------------------------

def offset_source(obj):
    """(source mesh object, library options) for an offset of `obj`: a GB result's source with
    its options, an offset object's stored source and options, or `obj` itself with the library's
    default options. Raises OffsetError."""
    if obj is None:
        raise OffsetError("GB Offset Surface: select a mesh object")
    s = obj.gbsurf
    if s.is_result or s.is_offset:
        src = core.live_source(obj)
        if src is None:
            raise OffsetError(f"{obj.name}: its source object is gone")
        return src, s.library_options()
    if obj.type != 'MESH':
        raise OffsetError(f"GB Offset Surface: {obj.name} is a {obj.type.lower()} object, select a mesh object")
    try:
        return obj, native.library_defaults()
    except native.GbsurfError as e:
        raise OffsetError(str(e)) from None


def read_source(src, depsgraph=None):
    """The (evaluated) mesh of `src` as `mesh_io.read_object` gives it. Raises OffsetError."""
    try:
        return mesh_io.read_object(src, depsgraph, vertex_groups=False)
    except mesh_io.SourceError as e:
        raise OffsetError(str(e)) from None


def compute_offset(src, lib_options, distance, grid, shell, data):
    """(positions, triangles, report) of the exact offset of the GB surface of `src`'s mesh
    `data` (from `read_source`). Raises OffsetError."""
    if lib_options["method"] not in PATCH_METHODS:
        raise OffsetError(f"{src.name}: the offset needs a patch method (Dual or Topology), "
                          f"not {lib_options['method']}")
    try:
        positions, sizes, indices = data
        if len(sizes) == 0:
            raise OffsetError(f"{src.name}: {core.NO_FACES}")
        opts = native.make_options(**lib_options)
        return offset_native.offset_mesh(positions, sizes, indices, opts, distance, grid, shell)
    except native.GbsurfError as e:
        raise OffsetError(f"{src.name}: {e}{core.evaluated_note(src)}") from None


def offset_info(positions, report):
    """(info text, warning or None) of an offset's report."""
    diag = float(np.linalg.norm(np.ptp(positions, axis=0))) if len(positions) else 0.0
    r = report
    text = (f"max gap {r['max_gap']:.3g}, cusps {r['cusps']}, singular pieces {r['singular_pieces']} "
            f"of {r['pieces']}, fit error {r['max_fit_error']:.3g}, offset error {r['max_offset_error']:.3g}"
            f"{', closed' if r['closed'] else ''}{', two-manifold' if r['two_manifold'] else ''}")
    problems = []
    if r["max_gap"] > GAP_WARN * max(diag, 1e-300):
        problems.append(f"gaps up to {r['max_gap']:.3g} between pieces ({r['unmatched_points']} unmatched points, "
                        f"{r['frame_seams']} frame seams)")
    if r["cusps"]:
        problems.append(f"{r['cusps']} cusp samples (|d| reaches the radius of curvature)")
    return text, ("; ".join(problems) or None)


def _fill(mesh, positions, triangles):
    mesh_io.write_triangles(mesh, positions, triangles)
    mesh_io.shade_smooth(mesh)


def _store(obj, src, lib_options, op):
    s = obj.gbsurf
    s.is_offset = True
    s.source = src
    for k, v in lib_options.items():
        setattr(s, k, v)
    s.offset_distance, s.offset_grid, s.offset_shell = op.offset_distance, op.offset_grid, op.offset_shell


def build_offset(src, lib_options, op, positions, triangles, info, data):
    """Creates `<src.name>.offset` (all or nothing); `data` is the source mesh it was made from
    (its digest lets live mode skip unchanged frames)."""
    created = []
    try:
        name = src.name + ".offset"
        mesh = bpy.data.meshes.new(name)
        created.append(mesh)
        _fill(mesh, positions, triangles)
        obj = bpy.data.objects.new(name, mesh)
        created.append(obj)
        core._link_like(obj, src)
        core._place_like(obj, src)
        _store(obj, src, lib_options, op)
        obj.gbsurf.info = info
        obj.gbsurf.source_digest = core.source_digest(data)
        core.remember_source_matrix(obj, src)
        return obj
    except Exception:
        core._remove_ids(created)
        raise


def regenerate(obj, depsgraph=None, data=None):
    """Regenerates the offset object `obj` from its source and stored settings (Update, and live
    mode in handlers.py): a new mesh with the old one's materials, the source followed
    (`core.follow_source`), info and digest stored. `data`: the source mesh already read
    (`read_source`). Returns (info, warning); raises OffsetError with nothing changed."""
    s = obj.gbsurf
    src, lib_options = offset_source(obj)
    if data is None:
        data = read_source(src, depsgraph)
    positions, triangles, report = compute_offset(
        src, lib_options, s.offset_distance, s.offset_grid, s.offset_shell, data)
    info, warning = offset_info(positions, report)
    old = obj.data
    mesh = bpy.data.meshes.new(old.name)
    try:
        _fill(mesh, positions, triangles)
    except Exception:
        bpy.data.meshes.remove(mesh)
        raise
    for m in old.materials:
        mesh.materials.append(m)
    obj.data = mesh
    core._remove_orphan(old)
    mesh.name = obj.name
    core.follow_source(obj, src)
    s.info = info
    s.source_digest = core.source_digest(data)
    return info, warning


def _in_object_mode(cls, context):
    """The surface offset operators' poll: Object Mode only, saying so otherwise."""
    if context.mode != 'OBJECT':
        cls.poll_message_set("Switch to Object Mode")
        return False
    return True


def _report_figures(op, obj, info, warning):
    if warning:
        op.report({'WARNING'}, f"{obj.name}: {warning}")
    op.report({'INFO'}, f"{obj.name}: {info}")


class OBJECT_OT_gbsurf_offset(OffsetOptionsMixin, bpy.types.Operator):
    """Add the exact offset of the active mesh's GB surface at a signed distance (a new object <name>.offset)"""

    bl_idname = "object.gbsurf_offset"
    bl_label = "GB Offset Surface"
    bl_options = {'REGISTER', 'UNDO'}

    @classmethod
    def poll(cls, context):
        return _in_object_mode(cls, context)

    def draw(self, context):
        layout = self.layout
        layout.use_property_split = True
        for name in ("offset_distance", "offset_shell", "offset_grid"):
            layout.prop(self, name)

    def execute(self, context):
        try:
            src, lib_options = offset_source(context.active_object)
            data = read_source(src, context.evaluated_depsgraph_get())
            positions, triangles, report = compute_offset(
                src, lib_options, self.offset_distance, self.offset_grid, self.offset_shell, data)
            info, warning = offset_info(positions, report)
            obj = build_offset(src, lib_options, self, positions, triangles, info, data)
        except (OffsetError, mesh_io.Float32RangeError) as e:
            self.report({'ERROR'}, str(e))
            return {'CANCELLED'}
        for o in context.selected_objects:
            o.select_set(False)
        obj.select_set(True)
        context.view_layer.objects.active = obj
        _report_figures(self, obj, info, warning)
        return {'FINISHED'}


class OBJECT_OT_gbsurf_offset_update(bpy.types.Operator):
    """Regenerate the active offset surface from its source mesh and stored settings"""

    bl_idname = "object.gbsurf_offset_update"
    bl_label = "Update GB Offset Surface"
    bl_options = {'REGISTER', 'UNDO'}

    @classmethod
    def poll(cls, context):
        obj = context.active_object
        return obj is not None and obj.gbsurf.is_offset

    def execute(self, context):
        obj = context.active_object
        try:
            info, warning = regenerate(obj, context.evaluated_depsgraph_get())
        except (OffsetError, mesh_io.Float32RangeError) as e:
            self.report({'ERROR'}, str(e))
            return {'CANCELLED'}
        _report_figures(self, obj, info, warning)
        return {'FINISHED'}


# --- PH offset of a planar Bezier curve ------------------------------------------------------------

def bezier_hermite_data(spline):
    """(points (K,3), tangents out (K,3), tangents in (K,3), cyclic) of a Bezier spline: the
    cubic segment derivatives 3(h_right - p) and 3(p - h_left) at each point."""
    n = len(spline.bezier_points)
    co, hl, hr = (np.empty(3 * n, dtype=np.float32) for _ in range(3))
    spline.bezier_points.foreach_get("co", co)
    spline.bezier_points.foreach_get("handle_left", hl)
    spline.bezier_points.foreach_get("handle_right", hr)
    co, hl, hr = (a.astype(np.float64).reshape(-1, 3) for a in (co, hl, hr))
    return co, 3.0 * (hr - co), 3.0 * (co - hl), bool(spline.use_cyclic_u)


def ph_spline(points, d_out, d_in, cyclic, name):
    """The PH quintic Hermite segments (list of (6,2) control points and the open
    `offset_native.Ph5Segment`s) through planar points with tangents. Raises OffsetError."""
    k = len(points)
    pairs = [(i, i + 1) for i in range(k - 1)] + ([(k - 1, 0)] if cyclic and k > 1 else [])
    if not pairs:
        raise OffsetError(f"{name}: a Bezier curve of at least two points is needed")
    segs = []
    try:
        for i, j in pairs:
            try:
                segs.append(offset_native.Ph5Segment(points[i], d_out[i], points[j], d_in[j]))
            except native.GbsurfError as e:
                raise OffsetError(f"{name}: segment {i} (points {i} and {j}): {e}") from None
    except Exception:
        for s in segs:
            s.free()
        raise
    return segs


def nurbs_quintic_points(segs):
    """Control points (5m+1, 2) of the order-6 NURBS (Bezier knots: interior multiplicity 5)
    made of m quintic Bezier segments."""
    cps = [s.control_points for s in segs]
    return np.vstack([cps[0]] + [c[1:] for c in cps[1:]])


def sample_offset(rationals, density):
    """Samples (N,2) of the exact offsets [(points, weights)] at `density` samples per
    segment (shared ends once) and their (segment, t) parameters."""
    t = np.linspace(0.0, 1.0, density + 1)
    pts, params = [], []
    for s, (p, w) in enumerate(rationals):
        ts = t if s == 0 else t[1:]
        pts.append(offset_native.rational_eval(p, w, ts))
        params.extend((s, float(x)) for x in ts)
    return np.vstack(pts), params


def _curve_object(name, src, kind_points, spline_type, z, created, order=None):
    cu = bpy.data.curves.new(name, 'CURVE')
    created.append(cu)
    cu.dimensions = '3D'
    sp = cu.splines.new(spline_type)
    xy = np.asarray(kind_points, dtype=np.float64)
    sp.points.add(len(xy) - 1)
    xyz = mesh_io.float32_positions(np.column_stack([xy, np.full(len(xy), z)]))
    co = np.column_stack([xyz, np.ones(len(xy), dtype=np.float32)])  # weights 1 (polynomial)
    sp.points.foreach_set("co", np.ascontiguousarray(co).reshape(-1))
    if order is not None:
        sp.order_u = order
        sp.use_endpoint_u = True
        sp.use_bezier_u = True
        sp.resolution_u = 16
    ob = bpy.data.objects.new(name, cu)
    created.append(ob)
    core._link_like(ob, src)
    core._place_like(ob, src)
    return ob


class CURVE_OT_gbsurf_ph_offset(bpy.types.Operator):
    """Fit a planar PH quintic spline through the active Bezier curve's points and handle tangents
    (in its local XY plane) and add it as an exact NURBS curve, with its exact offset as a poly
    curve (the rational form is kept in the custom property gbsurf_ph_offset)"""

    bl_idname = "curve.gbsurf_ph_offset"
    bl_label = "Exact Offset (PH)"
    bl_options = {'REGISTER', 'UNDO'}

    distance: FloatProperty(
        name="Distance", description="Signed offset distance (positive: right of the direction of travel)",
        default=0.1, subtype='DISTANCE', precision=4)
    density: IntProperty(
        name="Samples per Segment", description="Points of the offset poly curve per PH segment",
        default=32, min=1, max=4096)

    @classmethod
    def poll(cls, context):
        if context.mode not in {'OBJECT', 'EDIT_CURVE'}:
            cls.poll_message_set("Switch to Object Mode or edit a curve")
            return False
        return True

    def execute(self, context):
        from_edit = context.mode == 'EDIT_CURVE'
        if from_edit:
            # From the edit-mode Curve menu: leave Edit Mode first (writes the edits to the
            # curve); the new objects are selected in Object Mode. A failure returns to Edit Mode,
            # so a cancelled run leaves the user where they were.
            bpy.ops.object.mode_set(mode='OBJECT')
        src = context.active_object
        try:
            if src is None or src.type != 'CURVE':
                kind = f"{src.name} is a {src.type.lower()} object" if src is not None else "nothing is active"
                raise OffsetError(f"Exact Offset (PH): {kind}, select a Bezier curve")
            splines = [s for s in src.data.splines if s.type == 'BEZIER']
            if not splines:
                raise OffsetError(f"{src.name}: has no Bezier spline")
            if self.distance == 0.0 or not np.isfinite(self.distance):
                raise OffsetError(f"{src.name}: the offset distance must be non-zero and finite")
            points, d_out, d_in, cyclic = bezier_hermite_data(splines[0])
            notes = []
            if len(splines) > 1:
                notes.append(f"only the first of {len(splines)} Bezier splines is used")
            zs = np.concatenate([points[:, 2], points[:, 2] + d_out[:, 2], points[:, 2] - d_in[:, 2]])
            scale = max(float(np.ptp(points[:, :2], axis=0).max()), 1e-300)
            z = float(points[0, 2])
            if np.ptp(zs) > 1e-6 * scale:
                notes.append("the curve is not planar: its local XY projection is used")
                z = 0.0
            segs = ph_spline(points[:, :2], d_out[:, :2], d_in[:, :2], cyclic, src.name)
            try:
                rationals, cusps = [], []
                for i, s in enumerate(segs):
                    try:
                        p, w, c = s.offset(self.distance)
                    except native.GbsurfError as e:
                        raise OffsetError(f"{src.name}: offset of segment {i}: {e}") from None
                    rationals.append((p, w))
                    cusps.extend((i, x) for x in c)
                nurbs = nurbs_quintic_points(segs)
            finally:
                for s in segs:
                    s.free()
            samples, _ = sample_offset(rationals, self.density)
            record = {
                "distance": self.distance, "z": z, "degree": 9,
                "segments": [{"points": p.tolist(), "weights": w.tolist()} for p, w in rationals],
                "ph_segments": [nurbs[5 * i: 5 * i + 6].tolist() for i in range(len(segs))],
                "cusps": [[i, t] for i, t in cusps],
            }
            created = []
            try:
                ph = _curve_object(src.name + ".PH", src, nurbs, 'NURBS', z, created, QUINTIC_ORDER)
                off = _curve_object(src.name + ".PH_offset", src, samples, 'POLY', z, created)
                off[PH_OFFSET_PROPERTY] = json.dumps(record)
            except Exception as e:
                core._remove_ids(created)
                raise OffsetError(f"{src.name}: {e}") from None
        except (OffsetError, mesh_io.Float32RangeError) as e:
            self.report({'ERROR'}, str(e))
            if from_edit:
                bpy.ops.object.mode_set(mode='EDIT')
            return {'CANCELLED'}
        for o in context.selected_objects:
            o.select_set(False)
        ph.select_set(True)
        off.select_set(True)
        context.view_layer.objects.active = off
        for n in notes:
            self.report({'WARNING'}, f"{src.name}: {n}")
        if cusps:
            self.report({'WARNING'}, f"{off.name}: {len(cusps)} cusps of the offset at (segment, t) "
                        + ", ".join(f"({i}, {t:.4g})" for i, t in cusps[:10]))
        self.report({'INFO'}, f"{ph.name}: {len(segs)} PH quintic segments; {off.name}: "
                    f"{len(samples)} points, {len(cusps)} cusps")
        return {'FINISHED'}


classes = (OBJECT_OT_gbsurf_offset, OBJECT_OT_gbsurf_offset_update,
           CURVE_OT_gbsurf_ph_offset)


def register():
    for c in classes:
        bpy.utils.register_class(c)


def unregister():
    for c in reversed(classes):
        bpy.utils.unregister_class(c)
