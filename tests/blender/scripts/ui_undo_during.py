"""Undo: Ctrl+Z pressed while the live re-bake still runs (interactive, Xvfb): the job
ends and writes the colours of the undone move, then the add-on re-bakes for where undo put the
box. box_room.blend at MEDIUM, so that the update takes seconds."""
import os

import bpy

import rt_common as rt
import ui_steps as ui
from ui_moves import move, when_live_job
from ui_steps import out
from ui_undo import EXAMPLE, S, bake_button, bake_done, box, kept, op, quiet, settle_step



def setup():
    ui.install_and_open(os.path.abspath(EXAMPLE))
    bpy.context.scene.radiosity.preset = "MEDIUM"
    bpy.context.scene.radiosity.live = True
    op(bpy.ops.radiosity.show_colors)


def baked():
    S["C0"], S["P0"] = ui.colours(), tuple(box().location)


def undo_while_running(st):
    out["undo"] = op(bpy.ops.ed.undo)
    out["job_running_at_undo"] = ui.live_state().job is not None
    return None


def record():
    st = ui.live_state()
    stats = rt.last_stats()
    out["after"] = {"location": tuple(box().location), "stale": st.stale, "kept": kept(),
                    "runs": ui.live_runs() - S["runs"], "mode": stats["mode"],
                    "cached": stats.get("cached"), "nrmse_C0": rt.colours_nrmse(ui.colours(), S["C0"])}
    out["P0"] = S["P0"]
    ui.screenshot("undo_during_live")


ui.run(setup, bake_button, ui.Waiter(bake_done, 300, "the bake"), baked,
       move(box, lambda: bpy.context.scene["radiosity_move"]["location"], S),
       when_live_job(undo_while_running, S, "too_fast"), settle_step(),
       ui.Waiter(lambda: ui.live_runs() > S["runs"] and quiet(), 300, "live re-bakes"),
       settle_step(), record, ui.finish)
