"""UI: the `Object > Convert` entries (GB Surface, GB Offset Surface, Exact Offset (PH)), the
`Exact Offset (PH)` entry where curves are edited (the edit-mode `Curve` menu and the curve
context menus), and the Object properties panels of a result and of an offset surface (source,
settings, Update, Live)."""

import bpy

from .core import live_source
from .offset_ops import OBJECT_OT_gbsurf_offset_update
from .operators import OBJECT_OT_gbsurf_convert, OBJECT_OT_gbsurf_update
from .props import DISPLAY_ATTRIBUTE


def menu_convert(self, context):
    self.layout.operator(OBJECT_OT_gbsurf_convert.bl_idname, text="GB Surface")
    self.layout.operator("object.gbsurf_offset", text="GB Offset Surface")
    self.layout.operator("curve.gbsurf_ph_offset", text="Exact Offset (PH)")


def menu_curve(self, context):
    """`Exact Offset (PH)` in the edit-mode Curve menu and the curve context menus (the object
    context menu only when the active object is a curve)."""
    obj = context.active_object
    if obj is None or obj.type != 'CURVE':
        return
    self.layout.separator()
    self.layout.operator("curve.gbsurf_ph_offset", text="Exact Offset (PH)")


# Where a curve-editing artist looks (bpy 5.0 names): the header's Curve menu in Edit Mode, its
# context menu, and the Object Mode context menu.
CURVE_MENUS = ("VIEW3D_MT_edit_curve", "VIEW3D_MT_edit_curve_context_menu", "VIEW3D_MT_object_context_menu")


class _ObjectPropertiesPanel:
    """Where both panels live: the Object tab of the Properties editor."""

    bl_space_type = 'PROPERTIES'
    bl_region_type = 'WINDOW'
    bl_context = "object"


class OBJECT_PT_gbsurf(_ObjectPropertiesPanel, bpy.types.Panel):
    """Settings of a GB surface: edit them, then Update (or turn on Live)."""

    bl_label = "GB Surface"

    @classmethod
    def poll(cls, context):
        obj = context.object
        return obj is not None and obj.gbsurf.is_result

    def draw(self, context):
        s = context.object.gbsurf
        layout = self.layout
        layout.use_property_split = True
        layout.use_property_decorate = False
        layout.prop(s, "source")
        if live_source(context.object) is None:
            layout.label(text="The source object is gone", icon='ERROR')
        s.draw_options(layout.column())
        if s.method in {'DUAL', 'TOPOLOGY'}:
            layout.prop(s, "render_resolution")
        col = layout.column()
        col.prop(s, "display")
        if s.info:
            col.label(text=s.info, icon='INFO')
        row = layout.row(align=True)
        row.operator(OBJECT_OT_gbsurf_update.bl_idname, text="Update", icon='FILE_REFRESH')
        row.prop(s, "live", toggle=True, icon='REC' if s.live else 'PLAY')


class OBJECT_PT_gbsurf_offset(_ObjectPropertiesPanel, bpy.types.Panel):
    """Settings of an exact offset surface: edit them, then Update (or turn on Live)."""

    bl_label = "GB Offset Surface"

    @classmethod
    def poll(cls, context):
        obj = context.object
        return obj is not None and obj.gbsurf.is_offset

    def draw(self, context):
        s = context.object.gbsurf
        layout = self.layout
        layout.use_property_split = True
        layout.prop(s, "source")
        for name in ("offset_distance", "offset_shell", "offset_grid", "method", "resolution"):
            layout.prop(s, name)
        if s.info:
            layout.label(text=s.info, icon='INFO')
        row = layout.row(align=True)
        row.operator(OBJECT_OT_gbsurf_offset_update.bl_idname, text="Update", icon='FILE_REFRESH')
        row.prop(s, "live", toggle=True, icon='REC' if s.live else 'PLAY')


classes = (OBJECT_PT_gbsurf, OBJECT_PT_gbsurf_offset)


def register():
    for c in classes:
        bpy.utils.register_class(c)
    bpy.types.VIEW3D_MT_object_convert.append(menu_convert)
    for name in CURVE_MENUS:
        getattr(bpy.types, name).append(menu_curve)


def unregister():
    for name in CURVE_MENUS:
        getattr(bpy.types, name).remove(menu_curve)
    bpy.types.VIEW3D_MT_object_convert.remove(menu_convert)
    for c in reversed(classes):
        bpy.utils.unregister_class(c)
