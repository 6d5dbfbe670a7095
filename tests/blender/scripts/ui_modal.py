"""Interactive Blender (under Xvfb): the modal bake, Esc cancelling it, and undo.

Run: xvfb-run -a blender --factory-startup --enable-event-simulate --python ui_modal.py -- --zip Z
Steps are chained with bpy.app.timers because the modal operator needs the event loop.
"""
import json
import os
import sys
import time
import traceback

import bpy

import rt_common as rt
import scenes

out = {}
rt.setup()
scenes.build_diffuse_scene()
bpy.context.scene.radiosity.preset = "MEDIUM"


def ctx():
    win = bpy.context.window_manager.windows[0]
    area = next(a for a in win.screen.areas if a.type == "VIEW_3D") if any(
        a.type == "VIEW_3D" for a in win.screen.areas) else win.screen.areas[0]
    region = next(r for r in area.regions if r.type == "WINDOW")
    return dict(window=win, area=area, region=region, screen=win.screen)


def has_attr():
    return bpy.data.objects["Floor"].data.color_attributes.get("Radiosity") is not None


def finish():
    rt.result(**out)
    sys.stdout.flush()
    os._exit(0)         # quit_blender may ask to save; exit hard after printing


def guard(fn):
    def wrapped():
        try:
            return fn()
        except Exception:
            out["exception"] = traceback.format_exc()
            finish()
    return wrapped


state = {"t0": None}


@guard
def start_modal():
    with bpy.context.temp_override(**ctx()):
        bpy.ops.ed.undo_push(message="scene built")
        res = bpy.ops.radiosity.bake("INVOKE_DEFAULT")
    out["invoke"] = sorted(res)
    out["attr_right_after_invoke"] = has_attr()
    state["t0"] = time.monotonic()
    bpy.app.timers.register(wait_modal, first_interval=0.2)


@guard
def wait_modal():
    if not has_attr():
        if time.monotonic() - state["t0"] > 120:
            out["modal_timeout"] = True
            finish()
        return 0.2
    out["modal_done"] = True
    out["stats_after_modal"] = rt.last_stats()
    bpy.app.timers.register(do_undo, first_interval=0.5)
    return None


@guard
def do_undo():
    with bpy.context.temp_override(**ctx()):
        out["undo"] = sorted(bpy.ops.ed.undo())
    out["attr_after_undo"] = has_attr()
    out["stats_after_undo"] = bpy.context.scene.radiosity.last_stats
    bpy.app.timers.register(start_cancel, first_interval=0.5)


@guard
def start_cancel():
    props = bpy.context.scene.radiosity
    props.preset = "CUSTOM"
    props.error_threshold = 0.0005         # slow enough to cancel
    c = ctx()
    with bpy.context.temp_override(**c):
        bpy.ops.radiosity.clear()
        out["invoke2"] = sorted(bpy.ops.radiosity.bake("INVOKE_DEFAULT"))
    win = c["window"]
    win.event_simulate(type="ESC", value="PRESS")
    win.event_simulate(type="ESC", value="RELEASE")
    state["t0"] = time.monotonic()
    bpy.app.timers.register(after_cancel, first_interval=1.0)


@guard
def after_cancel():
    if time.monotonic() - state["t0"] < 5.0 and not sys.modules["radiosity"].bake.last_reports:
        return 0.2
    out["attr_after_cancel"] = has_attr()
    out["reports_after_cancel"] = [list(r) for r in sys.modules["radiosity"].bake.last_reports]
    bpy.app.timers.register(start_live, first_interval=0.5)


@guard
def start_live():
    """live on: a move is noticed by the depsgraph handler and re-baked by the timer."""
    props = bpy.context.scene.radiosity
    props.preset = "MEDIUM"
    props.live = True
    with bpy.context.temp_override(**ctx()):
        bpy.ops.radiosity.bake()                  # EXEC: synchronous
    box = bpy.data.objects["Box"]
    box.location.x -= 0.7                         # as a user would in the viewport
    state["runs0"] = _live_runs()
    state["t0"] = time.monotonic()
    bpy.app.timers.register(wait_live, first_interval=0.2)


def _live_runs():
    session = sys.modules["radiosity"].core.session
    return sum(x.live.runs for x in session.sessions().values())


@guard
def wait_live():
    if _live_runs() == state["runs0"]:
        if time.monotonic() - state["t0"] > 60:
            out["live_timeout"] = True
            finish()
        return 0.2
    import numpy as np
    live_vals = rt.corner_colors(bpy.data.objects["Floor"]).copy()
    out["live_stats"] = rt.last_stats()
    with bpy.context.temp_override(**ctx()):
        bpy.ops.radiosity.bake(full=True)
    full_vals = rt.corner_colors(bpy.data.objects["Floor"])
    out["live_runs"] = _live_runs() - state["runs0"]
    out["live_max_abs_diff"] = float(np.abs(live_vals - full_vals).max())
    out["live_floor_nrmse"] = float(np.sqrt(np.mean((live_vals - full_vals)[:, :3] ** 2))
                                    / np.sqrt(np.mean(full_vals[:, :3] ** 2)))
    finish()


bpy.app.timers.register(start_modal, first_interval=1.0)
