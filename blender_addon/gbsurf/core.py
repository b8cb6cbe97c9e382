"""The conversion work shared by the operators, live mode and the batch script.

Every function here computes first and creates Blender data last; if creating fails, what was
created is removed again, so a failure leaves the file as it was.
"""

import hashlib

import bpy
import numpy as np
from mathutils import Matrix

from . import mesh_io, native
from .props import DISPLAY_ATTRIBUTE, OPTION_NAMES, OUTPUT_DEFAULTS

MATERIAL_NAME = "GB Surface Color"


class ConvertError(Exception):
    """A conversion failed; the message is ready for `Operator.report`."""


# Library runs started by `compute` in this session (live mode's tests count them).
conversions = 0

VERTEX_GROUPS_SKIPPED = ("vertex groups not carried over: only Dual and Topology give the cage "
                         "coordinates they are interpolated with")
NO_FACES = "the mesh has no faces: fill it or add faces (F in Edit Mode)"
EVALUATED_NOTE = (" (element numbers are those of the mesh after its modifiers; disable them in "
                  "the viewport to see the edited mesh's)")


def has_enabled_modifiers(obj):
    """True if the object's evaluated mesh (what is converted) goes through a modifier shown in
    the viewport, so element numbers in errors are not those of the edited mesh."""
    mods = getattr(obj, "modifiers", None)
    if mods is None:
        return bool(getattr(obj, "modified", False))  # a worker thread's stand-in
    return any(m.show_viewport for m in mods)


def source_digest(data):
    """A digest of the mesh a conversion reads (positions, faces, creases): equal digests mean
    the same conversion input, so live mode can skip a frame whose source did not change."""
    h = hashlib.blake2b(digest_size=16)
    for a in data:
        h.update(np.ascontiguousarray(a).tobytes())
    for a in getattr(data, "creases", None) or ():  # (edges, sharpness, vertices, sharpness)
        h.update(np.ascontiguousarray(a).tobytes())
    return h.hexdigest()


def split_options(options):
    """(library options, output flags) from keyword options, the missing ones at their defaults
    (the library's, from `gbsurf_options_init`, and `OUTPUT_DEFAULTS`); unknown names raise."""
    unknown = set(options) - set(OPTION_NAMES) - set(OUTPUT_DEFAULTS)
    if unknown:
        raise ConvertError(f"unknown option(s): {', '.join(sorted(unknown))}")
    try:
        lib_options = native.library_defaults()
    except native.GbsurfError as e:
        raise ConvertError(str(e)) from None
    lib_options.update((k, v) for k, v in options.items() if k in OPTION_NAMES)
    outputs = {k: options.get(k, v) for k, v in OUTPUT_DEFAULTS.items()}
    return lib_options, outputs


def compute(obj, lib_options, outputs, progress=None, depsgraph=None, data=None):
    """Reads the (evaluated) source and runs the library: a `native.Conversion`.

    `data` = (positions, face_sizes, face_indices) skips reading (already read, e.g. by a
    thread-based caller). Raises ConvertError with a message naming the object."""
    global conversions
    name = getattr(obj, "name", "?")
    try:
        if data is None:
            data = mesh_io.read_object(obj, depsgraph)
        positions, sizes, indices = data
        if len(sizes) == 0:
            raise ConvertError(f"{name}: {NO_FACES}")
        opts = native.make_options(**lib_options)
        patch_method = lib_options["method"] in {'DUAL', 'TOPOLOGY'}
        conversions += 1
        conv = native.convert(
            positions, sizes, indices, opts, progress,
            creases=getattr(data, "creases", None),
            want_curves=patch_method and outputs.get("want_curves", False),
            want_control_net=patch_method and outputs.get("want_control_net", False),
        )
        conv.source_digest = source_digest(data)
        # Per cage face and corner: materials and UV maps; per cage vertex: vertex groups;
        # carried over by fill_surface.
        conv.source_faces = getattr(data, "faces", None)
        conv.source_face_sizes = sizes
        conv.source_face_indices = indices
        conv.source_vertex_groups = getattr(data, "vertex_groups", None)
        if conv.source_vertex_groups is not None and len(getattr(conv, "cage_coords", ())) == 0:
            conv.warnings.append(VERTEX_GROUPS_SKIPPED)
        return conv
    except native.Cancelled:
        raise ConvertError(f"{name}: cancelled") from None
    except native.GbsurfError as e:
        raise ConvertError(f"{name}: {e}{evaluated_note(obj)}") from None
    except mesh_io.SourceError as e:
        raise ConvertError(f"{e}{evaluated_note(obj)}") from None


def evaluated_note(obj):
    """What to add to an error naming elements of `obj`'s mesh: that they are those of the
    evaluated mesh when modifiers are enabled; else nothing."""
    return EVALUATED_NOTE if has_enabled_modifiers(obj) else ""


# --- building Blender data ---------------------------------------------------------------------

def surface_material(created=None):
    """A material showing the mesh's default colour attribute (shared by all results); a new
    one is appended to `created` (so a failed build removes it again)."""
    mat = bpy.data.materials.get(MATERIAL_NAME)
    if mat is not None and mat.library is None:
        return mat
    mat = bpy.data.materials.new(MATERIAL_NAME)
    if created is not None:
        created.append(mat)
    if bpy.app.version < (5, 0, 0):  # always node-based from 5.0 on (use_nodes deprecated)
        mat.use_nodes = True
    nt = mat.node_tree
    bsdf = next((n for n in nt.nodes if n.type == 'BSDF_PRINCIPLED'), None)
    if bsdf is None:
        bsdf = nt.nodes.new("ShaderNodeBsdfPrincipled")
    col = nt.nodes.new("ShaderNodeVertexColor")  # empty layer name: the render colour attribute
    col.location = (bsdf.location.x - 300, bsdf.location.y)
    nt.links.new(col.outputs["Color"], bsdf.inputs["Base Color"])
    bsdf.inputs["Roughness"].default_value = 0.4
    return mat


# The colour map of each display from the per-vertex attribute it shows. The stored sign of the
# mean curvature is the library's (H < 0 on convex regions, docs/math.md); the map shows convex
# warm and concave cool, as MeshLab's curvature maps: red for -H > 0.
_DISPLAY_COLORS = {
    'MEAN_CURVATURE': ("gb_mean_curvature", lambda v: mesh_io.diverging_colors(-v)),
    'G1': ("gb_g1_deviation", lambda v: mesh_io.sequential_colors(v, 1.0)),
    'PATCH': ("gb_patch", mesh_io.index_colors),
}


def set_display(mesh, display):
    """Makes the colour attribute of `display` the active and the render colour, computing it
    from its per-vertex attribute the first time it is shown: only the displayed colour layer is
    built with the mesh (three layers took 0.09 s of a 1.06 s conversion at 640k vertices)."""
    name = DISPLAY_ATTRIBUTE.get(display)
    if not name:
        return
    attr = mesh.color_attributes.get(name)
    if attr is None:
        source, colors = _DISPLAY_COLORS[display]
        if source not in mesh.attributes:
            return
        mesh_io.set_point_attribute(mesh, name, 'FLOAT_COLOR', colors(mesh_io.get_point_attribute(mesh, source)))
        attr = mesh.color_attributes.get(name)
        if attr is None:
            return
    mesh.color_attributes.active_color = attr
    if hasattr(mesh.attributes, "default_color_name"):
        mesh.attributes.default_color_name = name
    else:
        mesh.color_attributes.render_color_index = list(mesh.color_attributes).index(attr)


def fill_surface(mesh, conv, display='MEAN_CURVATURE', created=None, materials=None):
    """The output triangle mesh with smooth shading, its attributes and colours. `materials`
    (e.g. those of the mesh being replaced) are kept; by default the colour material."""
    mesh_io.write_triangles(mesh, conv.positions, conv.faces,
                            getattr(conv, "edges", None), getattr(conv, "corner_edges", None))
    mesh_io.shade_smooth(mesh)
    mesh_io.set_point_attribute(mesh, "gb_patch", 'INT', conv.patch_index.astype(np.int32))
    mesh_io.set_point_attribute(mesh, "gb_mean_curvature", 'FLOAT', conv.mean_curvature)
    mesh_io.set_point_attribute(mesh, "gb_gaussian_curvature", 'FLOAT', conv.gaussian_curvature)
    mesh_io.set_point_attribute(mesh, "gb_g1_deviation", 'FLOAT', conv.g1_deviation)
    # 1.0 where the surface folds (see the report's folds), else 0.0.
    mesh_io.set_point_attribute(mesh, "gb_fold", 'FLOAT', conv.fold)
    # The colour layer of the display (the others are made when first shown).
    set_display(mesh, display)
    loop_corner = getattr(conv, "cage_loop_corner", ())
    mesh_io.carry_cage_data(mesh, getattr(conv, "cage_corner", ()), getattr(conv, "cage_coords", ()),
                            getattr(conv, "source_face_sizes", ()), getattr(conv, "source_faces", None),
                            loop_corner)
    mesh_io.carry_vertex_groups(mesh, getattr(conv, "source_vertex_groups", None),
                                getattr(conv, "source_face_sizes", ()), getattr(conv, "source_face_indices", ()),
                                getattr(conv, "cage_corner", ()), getattr(conv, "cage_coords", ()),
                                getattr(conv, "faces", ()), loop_corner)
    for mat in (materials if materials else [surface_material(created)]):
        mesh.materials.append(mat)
    return mesh


def fill_curves(curve, curves):
    """One Bezier spline per curve of the network from its cubic chain (3k + 1 control points
    from the library: segment i is points 3i..3i+3), handles free; the outer handles of the
    first and last point mirror their inner ones."""
    curve.dimensions = '3D'
    for chain in curves:
        c = np.asarray(chain, dtype=np.float64).reshape(-1, 3)
        k = (len(c) - 1) // 3
        if k < 1:
            continue
        co = c[0::3]
        left = np.vstack([2 * c[:1] - c[1:2], c[2:-1:3]])
        right = np.vstack([c[1::3], 2 * c[-1:] - c[-2:-1]])
        sp = curve.splines.new('BEZIER')
        sp.bezier_points.add(k)
        bp = sp.bezier_points
        bp.foreach_set("co", co.astype(np.float32).reshape(-1))
        bp.foreach_set("handle_left", left.astype(np.float32).reshape(-1))
        bp.foreach_set("handle_right", right.astype(np.float32).reshape(-1))
        for p in bp:
            p.handle_left_type = p.handle_right_type = 'FREE'
    return curve


def fill_control_net(mesh, net):
    """The library's control net (`native.Conversion.control_net`): quads between ribbon rows,
    edges for one-row ribbons and the GB centre spokes, the patch per vertex as `gb_patch`."""
    edges = net["edges"] if len(net["edges"]) else None
    mesh_io.write_polygons(mesh, net["positions"], net["face_sizes"], net["face_indices"], edges)
    mesh_io.set_point_attribute(mesh, "gb_patch", 'INT', net["patch"].astype(np.int32))
    return mesh


def _editable(collection):
    return collection.library is None


def _link_like(new, src, collection=None):
    """Links `new` into `collection`, else into the source's collections that can take it (not
    linked from a library), else into the active collection or the scene's."""
    if collection is not None:
        cols = [collection]
    else:
        cols = [c for c in src.users_collection if _editable(c)]
    if not cols:
        active = getattr(bpy.context, "collection", None)
        cols = [active if active is not None and _editable(active) else bpy.context.scene.collection]
    for c in cols:
        c.objects.link(new)


def _place_like(new, src):
    """Gives `new` the parent relation and local transform of `src` (so it stays on the source
    when the parent moves); without a parent, the source's world matrix."""
    if src.parent is not None:
        new.parent = src.parent
        new.parent_type = src.parent_type
        if src.parent_type == 'BONE':
            new.parent_bone = src.parent_bone
        elif src.parent_type in {'VERTEX', 'VERTEX_3'}:
            new.parent_vertices = src.parent_vertices[:]
        new.matrix_parent_inverse = src.matrix_parent_inverse.copy()
        new.matrix_basis = src.matrix_basis.copy()
    else:
        new.matrix_world = src.matrix_world.copy()


def _frame(result, src):
    """The parent of both objects (their transforms are compared below it, so moving the parent
    moves both), else None (world space)."""
    p = src.parent
    return p if p is not None and result.parent == p else None


def _in_frame(obj, frame):
    m = obj.matrix_world
    return frame.matrix_world.inverted_safe() @ m if frame is not None else m.copy()


def remember_source_matrix(result, src):
    """Stores the source's transform the result is in sync with (see `follow_source`)."""
    m = _in_frame(src, _frame(result, src))
    result.gbsurf.source_matrix = [x for row in m for x in row]


def follow_source(result, src):
    """Places `result` on `src` keeping the transform relative to the source that the user gave
    it: result' = S_new · S_old⁻¹ · result, with S_old the source transform stored at the last
    sync (below a parent both share, else in world space). Without a stored (or with a singular)
    S_old the result snaps onto the source. Stores S_new."""
    frame = _frame(result, src)
    s_new = _in_frame(src, frame)
    flat = list(result.gbsurf.source_matrix)
    target = s_new
    if any(flat):
        s_old = Matrix([flat[0:4], flat[4:8], flat[8:12], flat[12:16]])
        if abs(s_old.determinant()) > 1e-12:
            target = s_new @ s_old.inverted() @ _in_frame(result, frame)
    world = frame.matrix_world @ target if frame is not None else target
    if any(abs(a - b) > 1e-6 for ra, rb in zip(result.matrix_world, world) for a, b in zip(ra, rb)):
        result.matrix_world = world
    result.gbsurf.source_matrix = [x for row in s_new for x in row]


def live_source(result):
    """The source object of a result if it still exists in some collection (deleting an object in
    the UI only unlinks it while our pointer holds a user), else None."""
    src = result.gbsurf.source
    if src is None or not src.users_collection:
        return None
    return src


def has_source(obj):
    """True for the objects made from a source with stored settings, which Update and live mode
    regenerate: GB results and exact offset surfaces (offset_ops)."""
    return obj.gbsurf.is_result or obj.gbsurf.is_offset


def is_result_part(obj):
    """True for GB results and for their curve-network / control-net objects."""
    if obj.gbsurf.is_result:
        return True
    p = obj.parent
    return p is not None and p.gbsurf.is_result and obj in (
        p.gbsurf.curves_object, p.gbsurf.net_object)


def _remove_ids(ids):
    for idb in reversed(ids):
        try:
            if isinstance(idb, bpy.types.Object):
                bpy.data.objects.remove(idb, do_unlink=True)
            elif isinstance(idb, bpy.types.Mesh):
                bpy.data.meshes.remove(idb, do_unlink=True)
            elif isinstance(idb, bpy.types.Curve):
                bpy.data.curves.remove(idb, do_unlink=True)
            elif isinstance(idb, bpy.types.Material):
                bpy.data.materials.remove(idb, do_unlink=True)
        except ReferenceError:
            pass


def _report_text(conv):
    r = conv.report
    text = f"{r['patches']} patches, {r['vertices']} vertices, {r['triangles']} triangles"
    if r["max_g1_deg"] > 0:
        text += f", max G1 {r['max_g1_deg']:.3g} deg"
    if not r["valid"]:
        # The same figures as the report's validity problems; `gb_fold` marks the folds.
        cage = r["input_self_intersections"]
        text += (f"; NOT VALID: {r['folds']} folded patches, {r['flipped_triangles']} flipped "
                 f"triangles, {r['self_intersections']} self-intersecting triangle pairs "
                 f"(input cage: {'not checked' if cage is None else cage})")
        if not r["closed"] and r["input_closed"]:
            text += ", open output"
    return text


def _make_extras(result, conv, outputs, created):
    """Creates / replaces / removes the curve and control-net objects of `result`."""
    s = result.gbsurf
    base = result.name
    for flag, attr, suffix, kind in (
        ("want_curves", "curves_object", ".curves", 'CURVE'),
        ("want_control_net", "net_object", ".net", 'MESH'),
    ):
        old = getattr(s, attr)
        if old is not None and old.parent != result:
            # Not ours (e.g. the pointer was copied with a duplicated result): leave it alone.
            setattr(s, attr, None)
            old = None
        data = None
        if outputs.get(flag) and (conv.curves if kind == 'CURVE' else _has_net(conv)):
            if kind == 'CURVE':
                data = bpy.data.curves.new(base + suffix, 'CURVE')
                created.append(data)
                fill_curves(data, conv.curves)
            else:
                data = bpy.data.meshes.new(base + suffix)
                created.append(data)
                fill_control_net(data, conv.control_net)
        if data is None:
            if old is not None:
                setattr(s, attr, None)
                old_data = old.data
                bpy.data.objects.remove(old, do_unlink=True)
                _remove_orphan(old_data)
            continue
        if old is not None and old.type == kind:
            old_data = old.data
            old.data = data
            _remove_orphan(old_data)
        else:
            ob = bpy.data.objects.new(base + suffix, data)
            created.append(ob)
            _link_like(ob, result)
            ob.parent = result
            setattr(s, attr, ob)


def _has_net(conv):
    return conv.control_net is not None and len(conv.control_net["positions"]) > 0


def _remove_orphan(data):
    if data is not None and data.users == 0:
        if isinstance(data, bpy.types.Mesh):
            bpy.data.meshes.remove(data)
        elif isinstance(data, bpy.types.Curve):
            bpy.data.curves.remove(data)


def build_result(src, conv, lib_options, outputs, collection=None):
    """Creates `<src.name>.GB` (plus extras) from a finished conversion; all or nothing."""
    created = []
    try:
        name = src.name + ".GB"
        mesh = bpy.data.meshes.new(name)
        created.append(mesh)
        # The source's material slots (material index per face carried over), else the colour one.
        src_mats = list(src.data.materials) if src.type == 'MESH' and any(src.data.materials) else None
        fill_surface(mesh, conv, created=created, materials=src_mats)
        obj = bpy.data.objects.new(name, mesh)
        created.append(obj)
        _link_like(obj, src, collection)
        _place_like(obj, src)
        s = obj.gbsurf
        s.is_result = True
        # Assign without triggering the live update callbacks (live is still off).
        s.source = src
        for k, v in {**lib_options, **outputs}.items():
            setattr(s, k, v)
        s.info = _report_text(conv)
        s.render_resolution = render_resolution_for(s.resolution)
        s.source_digest = getattr(conv, "source_digest", "")
        remember_source_matrix(obj, src)
        _make_extras(obj, conv, outputs, created)
        return obj
    except Exception:
        _remove_ids(created)
        raise


def render_resolution_for(resolution):
    """The default render resolution of a new result: one step finer than the viewport's (twice
    the samples per side, within the property's range)."""
    return min(2 * resolution, 1024)


def convert_object(obj, progress=None, depsgraph=None, collection=None, **options):
    """Converts one mesh object into a new object `<name>.GB` beside it and returns it.

    Keyword options: method ('DUAL', 'TOPOLOGY', 'DOO_SABIN', 'CATMULL_CLARK'), resolution,
    fullness, tile_depth, twist ('NONE', 'APPROX', 'INTERP'), mid_scale, middle ('SEED', 'FAIR'), best_plane, weights
    ('SQUARED', 'LINEAR'), levels, want_curves, want_control_net. `progress(fraction) -> bool`
    may cancel. Raises ConvertError; nothing is created then."""
    lib_options, outputs = split_options(options)
    conv = compute(obj, lib_options, outputs, progress, depsgraph)
    return build_result(obj, conv, lib_options, outputs, collection)


def compute_for(result, progress=None, depsgraph=None):
    """Runs the library for a result object's source and stored settings (no data changed)."""
    s = result.gbsurf
    if not s.is_result:
        raise ConvertError(f"{result.name}: not a GB surface")
    if live_source(result) is None:
        raise ConvertError(f"{result.name}: its source object is gone")
    if is_result_part(s.source):  # Python assignments bypass the pointer's poll
        raise ConvertError(f"{result.name}: its source {s.source.name} is a GB Surface output")
    return compute(s.source, s.library_options(), s.output_options(), progress, depsgraph)


def apply(result, conv):
    """Replaces a result object's mesh (and extras) by a finished conversion; all or nothing."""
    s = result.gbsurf
    created = []
    try:
        old = result.data
        mesh = bpy.data.meshes.new(old.name)
        created.append(mesh)
        # The user's materials on the old mesh stay (slots linked to the object stay anyway).
        fill_surface(mesh, conv, s.display, created, [m for m in old.materials if m is not None])
        result.data = mesh
        created.clear()  # the new mesh (and a new colour material) are in use now
        _remove_orphan(old)
        mesh.name = result.name
        if s.source is not None:
            follow_source(result, s.source)
        s.info = _report_text(conv)
        s.source_digest = getattr(conv, "source_digest", "")
        _make_extras(result, conv, s.output_options(), created)
    except Exception:
        _remove_ids(created)
        raise
    return result


def regenerate(result, progress=None, depsgraph=None):
    """Rebuilds a result object from its source and stored settings (the object stays, its mesh
    data is replaced). Raises ConvertError; the object is unchanged then."""
    return apply(result, compute_for(result, progress, depsgraph))
