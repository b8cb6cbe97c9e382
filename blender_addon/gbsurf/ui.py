"""UI: the `Object > Convert > GB Surface` menu entry and the Object properties panel of a result
(source, settings, outputs, colours, Update, Live)."""

import bpy

from .core import live_source
from .offset_ops import OBJECT_OT_gbsurf_offset_update
from .operators import OBJECT_OT_gbsurf_convert, OBJECT_OT_gbsurf_update
from .props import DISPLAY_ATTRIBUTE


def menu_convert(self, context):
    self.layout.operator(OBJECT_OT_gbsurf_convert.bl_idname, text="GB Surface")
    self.layout.operator("object.gbsurf_offset", text="GB Offset Surface")
    self.layout.operator("curve.gbsurf_ph_offset", text="Exact Offset (PH)")


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
    """Settings of an exact offset surface: edit them, then Update."""

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
        layout.operator(OBJECT_OT_gbsurf_offset_update.bl_idname, text="Update", icon='FILE_REFRESH')


classes = (OBJECT_PT_gbsurf, OBJECT_PT_gbsurf_offset)


def register():
    for c in classes:
        bpy.utils.register_class(c)
    bpy.types.VIEW3D_MT_object_convert.append(menu_convert)


def unregister():
    bpy.types.VIEW3D_MT_object_convert.remove(menu_convert)
    for c in reversed(classes):
        bpy.utils.unregister_class(c)
