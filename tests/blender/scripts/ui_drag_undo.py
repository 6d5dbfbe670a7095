"""A mouse drag and its undo in interactive Blender (Xvfb), through the window's own events:
G over the viewport, ten mouse moves in a viewport that draws slowly (each frame takes
--draw seconds, as software drawing of a furnished scene does: the steps then come slower
than Live's pause), a click; then Ctrl+Z.

Records per drag step whether a preview was shown (and if not, why), the colours after the
drag's live update, and after Ctrl+Z: whether the earlier bake's colours are back within one
redraw and whether any solve started.
"""
import time

import bpy
import numpy as np
from bpy_extras import view3d_utils

import rt_common as rt
import ui_steps as ui
from ui_steps import out
from ui_undo import bake_button, bake_done, box, scene, settle_step, setup  # the box room, its bake

STEPS = int(rt.arg("--steps", "10"))
POLL = 0.02                             # seconds between looks at a step's progress
DRAW = float(rt.arg("--draw", "0.8"))   # seconds each frame of the 3D viewport takes
STEP_TIMEOUT = 10.0
S = {}


def prepare():
    props = scene().radiosity
    props.preset = rt.arg("--preset", "MEDIUM")
    props.live = True
    with bpy.context.temp_override(**ui.ctx()):
        bpy.ops.radiosity.show_colors()


def first_bake():
    S["C0"] = ui.colours()
    S["P0"] = tuple(box().location)
    S["runs0"] = ui.live_runs()
    for o in bpy.context.view_layer.objects:
        o.select_set(o == box())
    bpy.context.view_layer.objects.active = box()


def box_on_screen():
    """Window coordinates of Box1's centre in the 3D viewport."""
    a = ui.area()
    region = next(r for r in a.regions if r.type == "WINDOW")
    rv3d = a.spaces.active.region_3d
    p = view3d_utils.location_3d_to_region_2d(region, rv3d, box().matrix_world.translation)
    return region.x + int(p.x), region.y + int(p.y)


def slow_frame():
    time.sleep(S.get("draw", 0.0))


def slow_drawing():
    """From here on each frame of the viewport takes DRAW seconds more."""
    S["draw"] = DRAW
    S["slow_handle"] = bpy.types.SpaceView3D.draw_handler_add(slow_frame, (), "WINDOW", "POST_VIEW")
    ui.area().tag_redraw()


def grab():
    x, y = box_on_screen()
    S["xy"] = (x, y)
    win = ui.window()
    win.event_simulate(type="MOUSEMOVE", value="NOTHING", x=x, y=y)
    win.event_simulate(type="G", value="PRESS", x=x, y=y)
    win.event_simulate(type="G", value="RELEASE", x=x, y=y)
    S["step_t"] = None
    S["steps"] = []
    S["previews_at_grab"] = ui.live_state().previews


def drag():
    """Step: the mouse moves on as soon as Blender has handled the last move, as a hand
    dragging on does (its next move is queued while the viewport draws). Records per move how
    long Blender took to handle it, and whether a live update was running by then; the
    previews shown during the drag are counted at its end."""
    st = ui.live_state()
    now = time.monotonic()
    if S["step_t"] is not None:
        moved = tuple(box().location) != S["location_before"]
        if now - S["step_t"] < STEP_TIMEOUT and not moved:
            return POLL
        S["steps"].append({"seconds": round(now - S["step_t"], 2), "moved": moved,
                           "job": st.job is not None, "skipped": st.preview_skipped})
        if len(S["steps"]) == STEPS:
            return None
    k = len(S["steps"])
    x, y = S["xy"]
    S["step_t"] = now
    S["location_before"] = tuple(box().location)
    ui.window().event_simulate(type="MOUSEMOVE", value="NOTHING", x=x + 6 * (k + 1), y=y + 3 * (k + 1))
    return POLL


def release():
    x, y = S["xy"]
    x, y = x + 6 * STEPS, y + 3 * STEPS
    win = ui.window()
    win.event_simulate(type="LEFTMOUSE", value="PRESS", x=x, y=y)
    win.event_simulate(type="LEFTMOUSE", value="RELEASE", x=x, y=y)
    out["steps"] = S["steps"]
    out["previews_during_drag"] = ui.live_state().previews - S["previews_at_grab"]
    out["P0"] = S["P0"]
    S["draw"] = 0.0
    bpy.types.SpaceView3D.draw_handler_remove(S["slow_handle"], "WINDOW")
    out["P0"] = S["P0"]
    out["moved_by"] = float(np.linalg.norm(np.array(box().location) - np.array(S["P0"])))


def last_preview():
    """The colours the drag's last preview left (the update writes only when it ends)."""
    S["last_preview"] = ui.colours()
    out["updates_written_before_last_preview"] = ui.live_runs() - S["runs0"]


def after_drag():
    S["C1"] = ui.colours()
    S["runs1"] = ui.live_runs()
    out["live_runs_for_drag"] = S["runs1"] - S["runs0"]
    out["drag_vs_C0"] = rt.colours_nrmse(S["C1"], S["C0"])
    # The last preview against the update at the same place: how close, and whether it showed
    # black (under a fifth of the update's value) where the update has light.
    out["preview_vs_update"] = rt.colours_nrmse(S["last_preview"], S["C1"])
    black = lit = 0
    for name, c in S["C1"].items():
        p = S["last_preview"].get(name)
        if p is None or p.shape != c.shape:
            continue
        v, w = c.mean(1), p.mean(1)
        light = v > 0.05 * max(v.mean(), 1e-12)
        lit += int(light.sum())
        dark = light & (w < 0.2 * v)
        black += int(dark.sum())
        if dark.any():
            out.setdefault("preview_black_by_object", {})[name] = [int(dark.sum()), float(v[dark].mean()),
                                                                 float(w[dark].mean()), float(v.mean())]
    out["preview_black"], out["preview_lit"] = black, lit
    ui.screenshot("1_after_drag")


def ctrl_z():
    x, y = S["xy"]
    win = ui.window()
    S["undo_t"] = time.monotonic()
    win.event_simulate(type="Z", value="PRESS", x=x, y=y, ctrl=True)
    win.event_simulate(type="Z", value="RELEASE", x=x, y=y, ctrl=True)


def one_redraw():
    """Right after Ctrl+Z has been handled (the next timer tick): what the meshes show."""
    st = ui.live_state()
    out["after_undo"] = {
        "seconds": time.monotonic() - S["undo_t"],
        "location_back": bool(np.allclose(box().location, S["P0"], atol=1e-4)),
        "vs_C0": rt.colours_nrmse(ui.colours(), S["C0"]),
        "vs_C1": rt.colours_nrmse(ui.colours(), S["C1"]),
        "job": st.job is not None, "pending": st.pending, "unjudged": st.unjudged,
    }


def later():
    st = ui.live_state()
    stats = rt.last_stats()
    out["later"] = {
        "vs_C0": rt.colours_nrmse(ui.colours(), S["C0"]),
        "live_runs": ui.live_runs() - S["runs1"],
        "job": st.job is not None, "stale": st.stale, "previews_written": st.previews,
        "mode": stats and stats.get("mode"), "full_reason": stats and stats.get("full_reason"),
    }
    ui.screenshot("2_after_undo")


if __name__ == "__main__":
    ui.run(setup, prepare, ui.open_sidebar, bake_button, ui.Waiter(bake_done, 300, "the bake"),
           settle_step(), first_bake, slow_drawing, ui.pause(2.0), grab, drag, release,
           ui.Waiter(lambda: not ui.live_state().preview_pending, 10, "the last preview"), last_preview,
           settle_step(), after_drag, ctrl_z, one_redraw, ui.pause(3.0), settle_step(), later,
           ui.finish, first=1.0)
