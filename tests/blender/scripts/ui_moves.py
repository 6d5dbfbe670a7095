"""A user's move of one object in interactive Blender and the live re-bake it starts: steps
for ui_steps.run, shared by the ui_*.py scripts that drag an object with Live on."""
import bpy
import numpy as np

import ui_steps as ui
from ui_steps import out


def move(obj, goal, state):
    """Step: obj() alone selected and active, moved to goal() by the Move operator, then the
    undo step a user's drag pushes. state["runs"] keeps the live runs before the move."""
    def step():
        moved = obj()
        for o in bpy.context.view_layer.objects:
            o.select_set(o == moved)
        bpy.context.view_layer.objects.active = moved
        state["runs"] = ui.live_runs()
        to = np.array(goal(), dtype=float)
        with bpy.context.temp_override(**ui.ctx()):     # as from a click in the 3D viewport
            bpy.ops.transform.translate(value=tuple(to - np.array(moved.location)))
            bpy.ops.ed.undo_push(message="Move")
    return step


def when_live_job(then, state, too_fast):
    """Step: waits for the live re-bake a move started, then returns then(live state) while its
    job runs. A re-bake that ended before a poll saw it (more live runs than state["runs"])
    sets out[too_fast] and ends the step."""
    def step():
        st = ui.live_state()
        if st.job is not None:
            return then(st)
        if ui.live_runs() > state["runs"]:
            out[too_fast] = True
            return None
        return ui.WAIT_STEP
    return step
