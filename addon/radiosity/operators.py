"""Operators: radiosity.bake, radiosity.clear, radiosity.show_colors, radiosity.restore_shading."""
import time

import bpy
from bpy.props import BoolProperty

from . import bake
from .core import job as core_job
from .core import session

TIMER_STEP = 0.1


def _report(op, level, message):
    bake.last_reports.append((level, message))
    op.report({level}, message)


def _report_warnings(op, run):
    for w in run.warnings:
        _report(op, "WARNING", w)


BAKE_TIP = ("Bake diffuse light into a colour attribute of every visible mesh. Updates the kept "
            "solution incrementally where it can (objects moved, added or removed, materials or "
            "lights changed), else solves from scratch")
FULL_TIP = ("Bake diffuse light into a colour attribute of every visible mesh, solving from "
            "scratch: the kept solution is dropped")


class RADIOSITY_OT_bake(bpy.types.Operator):
    # Blender shows bl_description as the tooltip verbatim (a docstring's line breaks too).
    bl_description = BAKE_TIP
    bl_idname = "radiosity.bake"
    bl_label = "Bake Radiosity"
    bl_options = {"REGISTER", "UNDO"}

    full: BoolProperty(name="From Scratch", default=False,
                       description="Ignore the kept solution and solve from scratch")

    @classmethod
    def poll(cls, context):
        return context.scene is not None and context.view_layer is not None

    @classmethod
    def description(cls, context, properties):
        # Bake and Full are this operator with two settings: each button says what it does.
        return FULL_TIP if properties.full else BAKE_TIP

    def _start(self, context):
        return bake.BakeRun(context.scene, context.view_layer,
                            context.evaluated_depsgraph_get(), self.full).prepare()

    def _done(self, run):
        _report_warnings(self, run)
        r = run.result
        _report(self, "INFO", f"Radiosity: {run.written} object(s) baked in {r['seconds']:.2f} s"
                              + (" (kept solution)" if r.get("cached") else ""))
        return {"FINISHED"}

    def _conclude(self, steps):
        """Run `steps`, which ends the bake and returns its run, and report the result; a
        BakeError on the way is reported as an error and cancels."""
        try:
            run = steps()
        except bake.BakeError as exc:
            _report(self, "ERROR", str(exc))
            return {"CANCELLED"}
        return self._done(run)

    def execute(self, context):
        bake.last_reports.clear()

        def solve():
            run = self._start(context)
            run.run_sync()
            run.finish()
            return run
        return self._conclude(solve)

    # -- modal job (UI) --------------------------------------------------------------------------
    def invoke(self, context, event):
        if bpy.app.background or context.window is None:
            return self.execute(context)
        bake.last_reports.clear()
        try:
            self._run = self._start(context)
            self._run.job.start()
        except bake.BakeError as exc:
            _report(self, "ERROR", str(exc))
            return {"CANCELLED"}
        self._t0 = time.monotonic()
        wm = context.window_manager
        self._timer = wm.event_timer_add(TIMER_STEP, window=context.window)
        wm.progress_begin(0, 100)
        wm.modal_handler_add(self)
        return {"RUNNING_MODAL"}

    def _cleanup(self, context):
        wm = context.window_manager
        wm.event_timer_remove(self._timer)
        wm.progress_end()
        if context.workspace is not None:
            context.workspace.status_text_set(None)

    def modal(self, context, event):
        run = self._run
        if event.type == "ESC":
            run.cancel()
            self._cleanup(context)
            _report(self, "WARNING", "Radiosity bake cancelled; nothing was written")
            return {"CANCELLED"}
        if event.type != "TIMER":
            return {"PASS_THROUGH"}
        progress = run.job.poll()
        context.window_manager.progress_update(int(progress * 100))
        if context.workspace is not None:
            context.workspace.status_text_set(status_text(run, progress,
                                                          time.monotonic() - self._t0))
        if run.job.state == core_job.RUNNING:
            return {"RUNNING_MODAL"}
        self._cleanup(context)

        def finish():
            if run.job.state == core_job.FAILED:
                raise bake.BakeError(f"solver failed: {run.job.error}")
            run.finish()
            return run
        return self._conclude(finish)


def status_text(run, progress, elapsed):
    """Status bar text of the modal bake. The native progress can rest on one figure for a
    while (it is reported between phases, not within them): the seconds show it is alive."""
    what = "updating" if run.job.mode == "incremental" and not run.job.is_cached else "solving"
    return (f"Radiosity: {what}… {progress * 100:.0f} %   {elapsed:.0f} s   (Esc to cancel)")


class RADIOSITY_OT_clear(bpy.types.Operator):
    bl_description = ("Free the memory the solver keeps to re-bake moves quickly (the baked "
                      "colours stay); the next bake solves from scratch")
    bl_idname = "radiosity.clear"
    bl_label = "Free Solver Memory"
    bl_options = {"REGISTER"}

    def execute(self, context):
        session.forget_kept(bake.scene_key(context.scene))
        return {"FINISHED"}


# Each 3D view's shading before Show Baked Colours is kept in the scene's session, by the
# view's address (UI data: undo does not touch it), so the user can go back.
_BAKED_SHADING = ("SOLID", "VERTEX", "FLAT")     # VERTEX is labelled "Attribute" in the UI


def _views(context):
    """The 3D view the button was pressed in, else every 3D view of the screen."""
    space = getattr(context, "space_data", None)
    if space is not None and space.type == "VIEW_3D":
        return [space]
    screen = context.screen
    if screen is None:
        return []
    return [s for a in screen.areas if a.type == "VIEW_3D" for s in a.spaces
            if s.type == "VIEW_3D"]


def _shading_of(space):
    sh = space.shading
    return (sh.type, sh.color_type, sh.light)


def shows_bake(space):
    return _shading_of(space) == _BAKED_SHADING


def any_shows_bake(context):
    return any(shows_bake(s) for s in _views(context))


def _reshade(op, context, shading_for):
    """Give each 3D viewport the shading `shading_for(space, saved)` returns, where `saved` is
    the scene's record of the viewports' shading before the bake was shown; no viewports (and
    a warning) in background mode."""
    views = _views(context)
    saved = session.session(bake.scene_key(context.scene)).shading
    if not views:
        op.report({"WARNING"}, "no 3D viewport (background mode?)")
        return {"CANCELLED"}
    for space in views:
        sh = space.shading
        sh.type, sh.color_type, sh.light = shading_for(space, saved)
    return {"FINISHED"}


class RADIOSITY_OT_show_colors(bpy.types.Operator):
    bl_description = ("Show the baked colours as they are: Solid shading, colour from the "
                      "active colour attribute, Flat lighting (Studio lighting would shade over "
                      "the bake)")
    bl_idname = "radiosity.show_colors"
    bl_label = "Show Baked Colours"
    bl_options = {"REGISTER"}

    def execute(self, context):
        def baked(space, saved):
            if not shows_bake(space):
                saved[space.as_pointer()] = _shading_of(space)
            return _BAKED_SHADING
        return _reshade(self, context, baked)


class RADIOSITY_OT_restore_shading(bpy.types.Operator):
    bl_description = "Go back to the viewport shading used before Show Baked Colours"
    bl_idname = "radiosity.restore_shading"
    bl_label = "Back to Previous Shading"
    bl_options = {"REGISTER"}

    def execute(self, context):
        def previous(space, saved):
            # Unknown (a file opened showing the bake): Blender's default Solid look.
            return saved.pop(space.as_pointer(), ("SOLID", "MATERIAL", "STUDIO"))
        return _reshade(self, context, previous)


CLASSES = (RADIOSITY_OT_bake, RADIOSITY_OT_clear, RADIOSITY_OT_show_colors,
           RADIOSITY_OT_restore_shading)


register, unregister = bpy.utils.register_classes_factory(CLASSES)
