"""Properties: the conversion options (shared by the operator and the stored settings) and the
settings a result object keeps (`Object.gbsurf`): its source, its options, its extra outputs and
the live flag.

The library options take their defaults from the library (`gbsurf_options_init`, read by
`native.library_defaults`) when the add-on registers; they are not repeated here.
"""

import bpy
from bpy.props import (
    BoolProperty,
    EnumProperty,
    FloatProperty,
    FloatVectorProperty,
    IntProperty,
    PointerProperty,
    StringProperty,
)

from . import native

METHOD_ITEMS = [
    ('DUAL', "Dual", "One n-sided GB patch per mesh vertex (dual structure)"),
    ('TOPOLOGY', "Topology", "One ribbon-only patch per mesh face (topology-preserving structure)"),
    ('DOO_SABIN', "Doo-Sabin", "Doo-Sabin subdivision (comparison, no patches)"),
    ('CATMULL_CLARK', "Catmull-Clark", "Catmull-Clark subdivision (comparison, no patches)"),
]
TWIST_ITEMS = [
    ('NONE', "None", "First approximation: G1 only where four-sided patches meet"),
    ('APPROX', "Approximating", "Approximating direction blend"),
    ('INTERP', "Interpolating", "Interpolating direction blend"),
]
MIDDLE_ITEMS = [
    ('SEED', "Seed", "Middle constraint of the direction blends by the seed's rule (times Mid Scale)"),
    ('FAIR', "Fair", "Middle constraint minimising the thin-plate energy of the curve's two patches"),
]
WEIGHT_ITEMS = [
    ('SQUARED', "Squared", "Squared correction weights (keep G1)"),
    ('LINEAR', "Linear", "Linear correction weights (comparison only)"),
]
DISPLAY_ITEMS = [
    ('MEAN_CURVATURE', "Mean Curvature",
     "Colour by mean curvature: convex warm (red), concave cool (blue), as MeshLab's curvature maps"),
    ('G1', "G1 Deviation", "Colour by the normal angle across patch boundaries"),
    ('PATCH', "Patches", "A colour per patch"),
]
DISPLAY_ATTRIBUTE = {
    'MEAN_CURVATURE': "gb_curvature_color",
    'G1': "gb_g1_color",
    'PATCH': "gb_patch_color",
}

# Names of the options that go to the library; the outputs (not library options) and their defaults.
OPTION_NAMES = native.OPTION_NAMES
OUTPUT_DEFAULTS = {"want_curves": False, "want_control_net": False}
OUTPUT_NAMES = tuple(OUTPUT_DEFAULTS)


def _settings_changed(self, context):
    # Only the stored settings of a live result regenerate on change (the operator's own copy of
    # these properties is re-run by Blender's redo instead).
    if isinstance(self, GbsurfSettings) and self.live and (self.is_result or self.is_offset):
        from . import handlers
        handlers.request_update(self.id_data)


class ConvertOptionsMixin:
    """The conversion options, as operator properties or stored settings (the library options'
    defaults are set by `apply_library_defaults`)."""

    method: EnumProperty(name="Method", items=METHOD_ITEMS, update=_settings_changed)
    face_layout: EnumProperty(name="Layout", items=[('QUADS', "Quads", "n·r² quads per patch, like Subdivision Surface level L at r = 2^(L-1)"), ('TRIANGLES', "Triangles", "n·r² triangles per patch")], update=_settings_changed)
    resolution: IntProperty(
        name="Resolution", description="Samples per patch side (subdivision methods: unused)",
        min=1, max=1024, soft_min=2, soft_max=32, update=_settings_changed)
    fullness: FloatProperty(
        name="Fullness", description="Fullness of the dual curves (0 <= k < 1)",
        min=0.0, max=0.99, update=_settings_changed)
    tile_depth: FloatProperty(
        name="Tile Depth", description="Tile split ratio of the topology structure (> 2)",
        min=2.01, soft_max=10.0, update=_settings_changed)
    twist: EnumProperty(name="Twist", items=TWIST_ITEMS, update=_settings_changed)
    mid_scale: FloatProperty(
        name="Mid Scale", description="Factor on the middle constraint of the direction blends",
        soft_min=0.0, soft_max=3.0, update=_settings_changed)
    middle: EnumProperty(name="Middle", items=MIDDLE_ITEMS, update=_settings_changed)
    best_plane: BoolProperty(
        name="Best Plane", description="Project onto best-fit planes",
        update=_settings_changed)
    weights: EnumProperty(name="Weights", items=WEIGHT_ITEMS, update=_settings_changed)
    levels: IntProperty(
        name="Levels", description="Subdivision levels of the comparison methods",
        min=0, max=8, soft_max=5, update=_settings_changed)
    max_memory_mb: IntProperty(
        name="Memory Limit (MiB)",
        description="A conversion estimated to need more memory is refused before any work",
        min=1, max=1 << 20, update=_settings_changed)
    want_curves: BoolProperty(
        name="Curve Network", description="Also create the boundary curves as a Bezier curve object",
        default=OUTPUT_DEFAULTS["want_curves"], update=_settings_changed)
    want_control_net: BoolProperty(
        name="Control Nets", description="Also create the patch control nets as a mesh object",
        default=OUTPUT_DEFAULTS["want_control_net"], update=_settings_changed)

    def library_options(self):
        """The library options as a dict."""
        return {name: getattr(self, name) for name in OPTION_NAMES}

    def output_options(self):
        return {name: getattr(self, name) for name in OUTPUT_NAMES}

    def draw_options(self, layout):
        layout.use_property_split = True
        layout.use_property_decorate = False
        layout.prop(self, "method")
        patch_method = self.method in {'DUAL', 'TOPOLOGY'}
        col = layout.column()
        if patch_method:
            col.prop(self, "face_layout")
            col.prop(self, "resolution")
            if self.method == 'DUAL':
                col.prop(self, "fullness")
            else:
                col.prop(self, "tile_depth")
            col.prop(self, "twist")
            # The middle constraint shapes the direction blends, which twist 'NONE' does not use.
            blend = col.column()
            blend.active = self.twist != 'NONE'
            blend.prop(self, "mid_scale")
            blend.prop(self, "middle")
            col.prop(self, "best_plane")
            col.prop(self, "weights")
        else:
            col.prop(self, "levels")
        layout.prop(self, "max_memory_mb")
        col = layout.column(heading="Outputs")
        sub = col.column()
        sub.active = patch_method
        sub.prop(self, "want_curves")
        sub.prop(self, "want_control_net")


class OffsetOptionsMixin:
    """The exact offset's settings (operator `object.gbsurf_offset` and offset objects)."""

    offset_distance: FloatProperty(
        name="Distance", description="Signed offset distance (negative: inward)", default=0.1,
        soft_min=-10.0, soft_max=10.0, subtype='DISTANCE', precision=4, update=_settings_changed)
    offset_shell: BoolProperty(
        name="Solid Shell", description="Close the surface and its offset into a solid", default=False,
        update=_settings_changed)
    offset_grid: IntProperty(
        name="Grid", description="PN pieces per patch side are a Grid x Grid grid (0: the library's default)",
        min=0, max=64, default=0, update=_settings_changed)


def _display_changed(self, context):
    from . import core
    if self.id_data is not None and self.id_data.type == 'MESH':
        core.set_display(self.id_data.data, self.display)


def _live_changed(self, context):
    if self.live and (self.is_result or self.is_offset):
        from . import handlers
        handlers.request_update(self.id_data)


def _poll_mesh(self, obj):
    from . import core
    return obj.type == 'MESH' and not core.is_result_part(obj)


class GbsurfSettings(ConvertOptionsMixin, OffsetOptionsMixin, bpy.types.PropertyGroup):
    """Stored on every result object: what it was made from and how."""

    is_result: BoolProperty(name="GB Surface", default=False)
    # An exact offset surface (offset_ops.py): its source and options are the fields below.
    is_offset: BoolProperty(name="GB Offset Surface", default=False)
    source: PointerProperty(
        name="Source", type=bpy.types.Object, poll=_poll_mesh,
        description="The control mesh this surface is made from", update=_settings_changed)
    curves_object: PointerProperty(name="Curve Network", type=bpy.types.Object)
    net_object: PointerProperty(name="Control Nets", type=bpy.types.Object)
    live: BoolProperty(
        name="Live", default=False, update=_live_changed,
        description="Regenerate whenever the source mesh or these settings change")
    display: EnumProperty(
        name="Color", items=DISPLAY_ITEMS, default='MEAN_CURVATURE', update=_display_changed,
        description="Which colour attribute is shown (viewport: Solid > Attribute, and renders)")
    info: StringProperty(name="Info", default="")
    render_resolution: IntProperty(
        name="Render Resolution", min=0, max=1024, soft_max=64, default=0,
        description="Samples per patch side in final renders (like Subdivision Surface's Render "
                    "levels); a new result gets twice its Resolution, 0 renders at Resolution")
    # The source's transform at the last sync (row-major 4x4; zeros: none stored), so Update and
    # live mode keep the result where the user moved it relative to its source (core.follow_source).
    source_matrix: FloatVectorProperty(size=16, default=(0.0,) * 16, options={'HIDDEN'})
    # Digest of the evaluated source mesh of the last conversion (core.source_digest): live mode
    # regenerates on a frame change only when it differs.
    source_digest: StringProperty(default="", options={'HIDDEN'})


classes = (GbsurfSettings,)


def apply_library_defaults():
    """Gives the library options of `ConvertOptionsMixin` the library's defaults; call before
    registering a class that uses it. Without a loadable library the properties keep Blender's
    zero defaults (converting then fails with the library-missing message anyway)."""
    try:
        defaults = native.library_defaults()
    except native.GbsurfError:
        return
    annotations = ConvertOptionsMixin.__annotations__
    for name, value in defaults.items():
        prop = annotations[name]
        annotations[name] = prop.function(**{**prop.keywords, "default": value})


def register():
    apply_library_defaults()
    for c in classes:
        bpy.utils.register_class(c)
    bpy.types.Object.gbsurf = PointerProperty(type=GbsurfSettings)


def unregister():
    del bpy.types.Object.gbsurf
    for c in reversed(classes):
        bpy.utils.unregister_class(c)
