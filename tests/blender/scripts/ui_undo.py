"""Undo in interactive Blender (Xvfb): undo and redo after a live re-bake leave colours that
match the scene, and keep the kept solution.

The user's path: open box_room.blend, Live on, Bake, move Box1 with the Move operator (an undo
step, as a drag makes), let Live re-bake, Ctrl+Z, Ctrl+Shift+Z; then with Live off: move, Bake,
undo (the bake is out of date and the panel says so), Bake again (the kept solution rewrites
the colours without solving).
"""
import os

import bpy
import numpy as np

import rt_common as rt
import ui_steps as ui
from ui_steps import out

EXAMPLE = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "..",
                       "example_blends", "box_room.blend")
S = {}


def scene():
    return bpy.context.scene


def box():
    return bpy.data.objects["Box1"]


def kept():
    mod = ui.addon()
    return mod.core.session.kept(mod.bake.scene_key(scene())) is not None


def quiet():
    """No live re-bake queued or running (for a moment: the debounce may still queue one)."""
    st = ui.live_state()
    return st.job is None and not st.pending


def settle_step():
    """Wait until Live has been quiet for 1.5 s."""
    t = {"since": None}
    import time

    def step():
        now = time.monotonic()
        if not quiet():
            t["since"] = None
            return ui.WAIT_STEP
        if t["since"] is None:
            t["since"] = now
        if now - t["since"] < 1.5:
            return ui.WAIT_STEP
        t["since"] = None
        return None
    return step


def op(fn, *args, **kw):
    with bpy.context.temp_override(**ui.ctx()):
        return sorted(fn(*args, **kw))


def push(message):
    """Operators called from a script push no undo step (the script's caller would); a user's
    Move or Bake does, so the script pushes what the user's click would have."""
    op(bpy.ops.ed.undo_push, message=message)


def bake_button():
    """Bake as the button does (the modal job; its undo step is pushed when it finishes)."""
    S["bake_token"] = scene().radiosity.last_stats
    out.setdefault("invoke", []).append(op(bpy.ops.radiosity.bake, "INVOKE_DEFAULT"))


def bake_done():
    return scene().radiosity.last_stats != S["bake_token"] and quiet()


def setup():
    ui.install_and_open(os.path.abspath(EXAMPLE))


def prepare():
    props = scene().radiosity
    props.preset = "DRAFT"
    props.live = True
    op(bpy.ops.radiosity.show_colors)


def first_bake():
    S["C0"], S["P0"] = ui.colours(), tuple(box().location)
    out["stats0_mode"] = rt.last_stats()["mode"]


def move_to(target, how="translate"):
    def step():
        for o in bpy.context.view_layer.objects:
            o.select_set(o == box())
        bpy.context.view_layer.objects.active = box()
        S["runs_before_move"] = ui.live_runs()
        goal = np.array(target() if callable(target) else target, dtype=float)
        if how == "translate":
            out.setdefault("moves", []).append(op(bpy.ops.transform.translate,
                                                  value=tuple(goal - np.array(box().location))))
        else:
            push("before the move")
            box().location = tuple(goal)
        push("Move")
    return step


def touch_during_job():
    """A transform update that moves nothing while the live job runs (Blender sends such
    updates, e.g. when the Move operator's undo step is pushed): it must not queue a second
    re-bake, which used to overwrite the update's stats with a cached rewrite."""
    st = ui.live_state()
    if st.job is None and ui.live_runs() == S["runs_before_move"]:
        return ui.WAIT_STEP
    out["touched_during_job"] = st.job is not None
    box().location = tuple(box().location)
    return None


def after_live():
    st = ui.live_state()
    S["C1"], S["P1"] = ui.colours(), tuple(box().location)
    out["live_runs_for_move"] = ui.live_runs() - S["runs_before_move"]
    out["stats1"] = rt.last_stats()
    out["stale_after_live"] = st.stale
    ui.screenshot("1_after_live_update")


def undo():
    S["runs_before_undo"] = ui.live_runs()
    out.setdefault("undo", []).append(op(bpy.ops.ed.undo))


def judged():
    """The add-on judges the colours once Blender has evaluated the undone scene."""
    st = ui.live_state()
    if st.unjudged:
        return ui.WAIT_STEP
    out.setdefault("stale_right_after_undo", []).append(st.stale)
    return None


def redo():
    S["runs_before_undo"] = ui.live_runs()
    out.setdefault("redo", []).append(op(bpy.ops.ed.redo))


def record(name, against):
    def step():
        st = ui.live_state()
        stats = rt.last_stats()
        out[name] = {
            "location": tuple(box().location), "stale": st.stale, "kept": kept(),
            "live_runs": ui.live_runs() - S["runs_before_undo"],
            "mode": stats and stats["mode"], "cached": stats and stats.get("cached"),
            "full_reason": stats and stats.get("full_reason"),
            "nrmse": {k: rt.colours_nrmse(ui.colours(), S[k]) for k in against},
        }
        ui.screenshot(name)
    return step


def live_off_move():
    scene().radiosity.live = False
    S["runs_before_undo"] = ui.live_runs()


def live_off_record_moved():
    out["live_off_stale_after_move"] = ui.live_state().stale
    out["live_off_runs_after_move"] = ui.live_runs() - S["runs_before_undo"]
    ui.screenshot("4_live_off_moved")


def bake_again(name):
    def step():
        S[name] = ui.colours()
        stats = rt.last_stats()
        out[name] = {"mode": stats["mode"], "cached": stats.get("cached"),
                     "source": stats.get("source"), "stale": ui.live_state().stale,
                     "full_reason": stats.get("full_reason")}
    return step


def compare_rebake():
    out["rebake_vs_C2"] = rt.colours_nrmse(ui.colours(), S["C2"])


def undo_to_start():
    """Undo until no mesh holds colours (past the first bake): the kept solution stays."""
    for _ in range(12):
        if not ui.colours():
            break
        op(bpy.ops.ed.undo)
    out["start"] = {"colours": bool(ui.colours()), "kept": kept(),
                    "stale": ui.live_state().stale, "stats": scene().radiosity.last_stats}


def pressed_bake():
    return [bake_button, ui.Waiter(bake_done, 120, "the bake")]


if __name__ == "__main__":       # ui_undo_during.py imports the steps
    ui.run(
        setup, prepare, ui.open_sidebar, ui.click_radiosity_tab, *pressed_bake(), first_bake,
        move_to(lambda: scene()["radiosity_move"]["location"], rt.arg("--move", "translate")),
        touch_during_job,
        ui.Waiter(lambda: ui.live_runs() > S["runs_before_move"] and quiet(), 120, "live re-bake"),
        settle_step(), after_live,
        undo, judged, settle_step(), record("2_after_undo", ("C0", "C1")),
        redo, settle_step(), record("3_after_redo", ("C0", "C1")),
        live_off_move, move_to(lambda: np.array(S["P1"]) + np.array((-40.0, 30.0, 0.0))),
        settle_step(), live_off_record_moved,
        *pressed_bake(), bake_again("C2"),
        undo, judged, settle_step(), record("5_live_off_after_undo", ("C1", "C2")),
        *pressed_bake(), bake_again("C3"), compare_rebake,
        undo_to_start, ui.finish, first=1.0)
