"""The panel in interactive Blender (Xvfb, 1600x1000): box_room.blend opens looking
through its camera; the panel's words, tooltips and buttons; Show Baked Colours shows the bake
with Flat lighting and the user can go back.
"""
import os
import time

import bpy

import rt_common as rt
import ui_steps as ui
from ui_steps import out

EXAMPLE = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "..",
                       "example_blends", "box_room.blend")
S = {}


def scene():
    return bpy.context.scene


def op(fn, *args, region="WINDOW", **kw):
    with bpy.context.temp_override(**ui.ctx(region=region)):
        return sorted(fn(*args, **kw))


def setup():
    ui.install_and_open(os.path.abspath(EXAMPLE))


def opened():
    space = ui.area().spaces.active
    out["opened_view"] = space.region_3d.view_perspective
    out["camera"] = scene().camera.name if scene().camera else None
    ui.screenshot("0_opened")


def shading():
    sh = ui.area().spaces.active.shading
    return [sh.type, sh.color_type, sh.light]


def bake():
    scene().radiosity.preset = "DRAFT"
    S["before"] = scene().radiosity.last_stats
    out["invoke"] = op(bpy.ops.radiosity.bake, "INVOKE_DEFAULT")


def words():
    mod = ui.addon()
    stats = rt.last_stats()
    out["describe"] = mod.core.stats.describe(stats)
    # The tooltips Blender shows for the two buttons: the operator's description() with the
    # button's own properties (real OperatorProperties, as the UI passes them).
    props = bpy.context.window_manager.operator_properties_last("radiosity.bake")
    cls = mod.operators.RADIOSITY_OT_bake
    props.full = False
    out["tip_bake"] = cls.description(bpy.context, props)
    props.full = True
    out["tip_full"] = cls.description(bpy.context, props)
    props.full = False
    clear = bpy.ops.radiosity.clear.get_rna_type()
    out["clear_label"], out["clear_tip"] = clear.name, clear.description
    out["shading_before"] = shading()


def show_colours():
    # As the sidebar's button: the context of the 3D viewport's sidebar region.
    out["show"] = op(bpy.ops.radiosity.show_colors, region="UI")
    out["shading_shown"] = shading()
    out["panel_offers_back"] = ui.addon().operators.shows_bake(ui.area().spaces.active)


def shot_flat():
    ui.screenshot("1_baked_flat_panel")


def hover(name, from_right, from_top):
    """Hover a panel button for its tooltip: a picture for the eye (the position is where the
    panel draws the button in a 1600x1000 window at UI scale 1)."""
    def step():
        if "t_hover" not in S:
            reg = next(r for r in ui.area().regions if r.type == "UI")
            x, y = reg.x + reg.width - from_right, reg.y + reg.height - from_top
            ui.window().event_simulate(type="MOUSEMOVE", value="NOTHING", x=x, y=y)
            S["t_hover"] = time.monotonic()
        if time.monotonic() - S["t_hover"] < 3.0:
            return ui.WAIT_STEP
        del S["t_hover"]
        ui.screenshot("2_tooltip_" + name)
        mid = next(r for r in ui.area().regions if r.type == "WINDOW")
        ui.window().event_simulate(type="MOUSEMOVE", value="NOTHING", x=mid.x + 40, y=mid.y + 40)
        return None
    return step


def restore():
    out["restore"] = op(bpy.ops.radiosity.restore_shading, region="UI")
    out["shading_restored"] = shading()
    out["panel_offers_show"] = not ui.addon().operators.shows_bake(ui.area().spaces.active)


def restored_shot():
    ui.screenshot("3_restored")


ui.run(setup, opened, ui.open_sidebar, ui.click_radiosity_tab, bake,
       ui.Waiter(lambda: scene().radiosity.last_stats != S["before"], 120, "the bake"),
       words, show_colours, shot_flat, hover("bake", 160, 255), hover("full", 40, 255),
       hover("forget", 80, 303), restore, ui.pause(1.0), restored_shot, ui.finish)
