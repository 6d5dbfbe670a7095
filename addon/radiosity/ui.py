"""Panels: 3D viewport sidebar (tab "Radiosity") and Render properties."""
import json

import bpy


def draw_settings(layout, context):
    props = context.scene.radiosity
    col = layout.column()
    col.prop(props, "preset")
    sub = col.row()
    sub.enabled = props.preset == "CUSTOM"
    sub.prop(props, "error_threshold")
    col.prop(props, "attribute_name")
    col.prop(props, "lighting_only")
    col.prop(props, "adaptive_mesh")
    col.prop(props, "byte_copy")
    sub = col.row()
    sub.enabled = props.byte_copy
    sub.prop(props, "exposure")
    col.prop(props, "live")
    row = layout.row(align=True)
    row.operator("radiosity.bake", text="Bake", icon="RENDER_STILL").full = False
    row.operator("radiosity.bake", text="Full", icon="FILE_REFRESH").full = True
    row = layout.row(align=True)
    row.operator("radiosity.show_colors", icon="SHADING_SOLID")
    row.operator("radiosity.clear", text="", icon="TRASH")
    draw_stats(layout, props.last_stats)


def draw_stats(layout, text):
    if not text:
        return
    try:
        data = json.loads(text)
    except ValueError:
        return
    box = layout.box()
    box.label(text=f"Last bake: {data.get('mode', '?')}"
                   f"{' (kept)' if data.get('cached') else ''}, {data.get('seconds', 0):.2f} s")
    for key in ("objects", "input_surfaces", "elements", "links", "rays"):
        box.label(text=f"{key.replace('_', ' ').capitalize()}: {data.get(key, 0):,}")


class RADIOSITY_PT_view3d(bpy.types.Panel):
    bl_label = "Radiosity"
    bl_space_type = "VIEW_3D"
    bl_region_type = "UI"
    bl_category = "Radiosity"

    def draw(self, context):
        draw_settings(self.layout, context)


class RADIOSITY_PT_render(bpy.types.Panel):
    bl_label = "Radiosity"
    bl_space_type = "PROPERTIES"
    bl_region_type = "WINDOW"
    bl_context = "render"
    bl_options = {"DEFAULT_CLOSED"}

    def draw(self, context):
        draw_settings(self.layout, context)


CLASSES = (RADIOSITY_PT_view3d, RADIOSITY_PT_render)


def register():
    for c in CLASSES:
        bpy.utils.register_class(c)


def unregister():
    for c in reversed(CLASSES):
        bpy.utils.unregister_class(c)
