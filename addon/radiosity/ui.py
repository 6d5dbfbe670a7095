"""Panels: 3D viewport sidebar (tab "Radiosity") and Render properties."""
import json
import textwrap
import time

import bpy

from . import handlers, operators
from .core import stats as core_stats

CHAR_PIXELS = 7         # about one character of the UI font at scale 1 (for wrapping only)


def _chars(context):
    """Characters a label fits in this region: long lines are wrapped, never cut to '…'."""
    region = getattr(context, "region", None)
    width = region.width if region is not None and region.width > 1 else 300
    scale = context.preferences.system.ui_scale if context.preferences else 1.0
    return max(16, int((width - 30) / (CHAR_PIXELS * scale)))


def _wrapped(layout, text, chars, icon="NONE"):
    col = layout.column(align=True)
    col.scale_y = 0.8       # the lines of one text closer than separate labels
    for i, line in enumerate(textwrap.wrap(text, chars) or [""]):
        col.label(text=line, icon=icon if i == 0 else "BLANK1" if icon != "NONE" else "NONE")


def draw_settings(layout, context):
    props = context.scene.radiosity
    chars = _chars(context)
    col = layout.column()
    col.prop(props, "preset")
    if props.preset == "CUSTOM":
        col.prop(props, "error_threshold")
    # The sidebar is narrow: a label beside the text field was cut to 'Attrib...'.
    col.label(text="Colour Attribute:")
    col.prop(props, "attribute_name", text="")
    col.prop(props, "lighting_only")
    col.prop(props, "adaptive_mesh")
    col.prop(props, "byte_copy")
    sub = col.row()
    sub.enabled = props.byte_copy
    sub.prop(props, "exposure")
    col.prop(props, "live")
    row = layout.row(align=True)
    row.operator("radiosity.bake", text="Bake", icon="RENDER_STILL").full = False
    row.operator("radiosity.bake", text="From Scratch", icon="FILE_REFRESH").full = True
    col = layout.column(align=True)
    if operators.any_shows_bake(context):
        col.operator("radiosity.restore_shading", icon="LOOP_BACK")
    else:
        col.operator("radiosity.show_colors", icon="SHADING_SOLID")
    col.operator("radiosity.clear", icon="TRASH")
    st = handlers.settle(context.scene, writes=False)
    draw_state(layout, st, props.live, chars)
    shown = st.shown.record.stats if st is not None and st.shown.record is not None else None
    draw_stats(layout, json.dumps(shown) if shown else props.last_stats, chars)


def draw_state(layout, st, live, chars=40):
    """A live re-bake running or queued, or why the colours shown are out of date."""
    if st is None:
        return
    if st.job is not None:
        elapsed = time.monotonic() - (st.job_started or time.monotonic())
        _wrapped(layout.box(), f"Live update: {st.progress * 100:.0f} %, {elapsed:.0f} s", chars,
                 icon="SORTTIME")
        return
    if st.pending and live:
        layout.box().label(text="Live update queued", icon="SORTTIME")
        return
    if st.failed and live:
        box = layout.box()
        box.alert = True
        box.label(text="Live update failed", icon="ERROR")
        _wrapped(box, st.failed, chars)
    reason = st.stale
    if reason:
        box = layout.box()
        box.alert = True
        box.label(text="Bake out of date", icon="ERROR")
        _wrapped(box, reason[0].upper() + reason[1:] + ".", chars)
        if not live:
            _wrapped(box, "Press Bake (or turn Live on) to update.", chars)


def draw_stats(layout, text, chars=40):
    if not text:
        return
    try:
        data = json.loads(text)
    except ValueError:
        return
    d = core_stats.describe(data)
    if not d["headline"]:
        return
    box = layout.box()
    _wrapped(box, d["headline"], chars)
    for line in d["details"]:
        _wrapped(box, line, chars)
    col = box.column(align=True)
    for label, value in d["counts"]:
        col.label(text=f"{label}: {int(value or 0):,}")


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


register, unregister = bpy.utils.register_classes_factory(CLASSES)
