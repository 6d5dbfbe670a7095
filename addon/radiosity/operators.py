"""Operators: radiosity.bake, radiosity.clear, radiosity.show_colors."""
import bpy
from bpy.props import BoolProperty

from . import bake
from .core import job as core_job
from .core import live as core_live

TIMER_STEP = 0.1


def _report(op, level, message):
    bake.last_reports.append((level, message))
    op.report({level}, message)


def _report_warnings(op, run):
    for w in run.warnings:
        _report(op, "WARNING", w)


class RADIOSITY_OT_bake(bpy.types.Operator):
    """Bake diffuse global illumination into a colour attribute of every visible mesh"""
    bl_idname = "radiosity.bake"
    bl_label = "Bake Radiosity"
    bl_options = {"REGISTER", "UNDO"}

    full: BoolProperty(name="Full", default=False,
                       description="Ignore the kept solution and solve from scratch")

    @classmethod
    def poll(cls, context):
        return context.scene is not None and context.view_layer is not None

    def _start(self, context):
        return bake.BakeRun(context.scene, context.view_layer,
                            context.evaluated_depsgraph_get(), self.full).prepare()

    def _done(self, run):
        _report_warnings(self, run)
        r = run.result
        _report(self, "INFO", f"Radiosity: {run.written} object(s) baked in {r['seconds']:.2f} s"
                              + (" (kept solution)" if r.get("cached") else ""))
        return {"FINISHED"}

    def execute(self, context):
        bake.last_reports.clear()
        try:
            run = self._start(context)
            run.run_sync()
            run.finish()
        except bake.BakeError as exc:
            _report(self, "ERROR", str(exc))
            return {"CANCELLED"}
        return self._done(run)

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
            context.workspace.status_text_set(
                f"Radiosity: solving… {progress * 100:.0f} %   (Esc to cancel)")
        if run.job.state == core_job.RUNNING:
            return {"RUNNING_MODAL"}
        self._cleanup(context)
        try:
            if run.job.state == core_job.FAILED:
                raise bake.BakeError(f"solver failed: {run.job.error}")
            run.finish()
        except bake.BakeError as exc:
            _report(self, "ERROR", str(exc))
            return {"CANCELLED"}
        return self._done(run)


class RADIOSITY_OT_clear(bpy.types.Operator):
    """Drop the kept radiosity solution (the next bake solves from scratch)"""
    bl_idname = "radiosity.clear"
    bl_label = "Clear Radiosity Solution"
    bl_options = {"REGISTER"}

    def execute(self, context):
        key = bake.scene_key(context.scene)
        core_job.cache_drop(key)
        core_live.state_for(key).transforms.clear()
        return {"FINISHED"}


class RADIOSITY_OT_show_colors(bpy.types.Operator):
    """Show colour attributes in the 3D viewports' Solid shading"""
    bl_idname = "radiosity.show_colors"
    bl_label = "Show Baked Colours"
    bl_options = {"REGISTER"}

    def execute(self, context):
        screen = context.screen
        if screen is None:
            self.report({"WARNING"}, "no screen (background mode?)")
            return {"CANCELLED"}
        for area in screen.areas:
            if area.type == "VIEW_3D":
                for space in area.spaces:
                    if space.type == "VIEW_3D":
                        space.shading.type = "SOLID"
                        space.shading.color_type = "VERTEX"   # labelled "Attribute" in the UI
        return {"FINISHED"}


CLASSES = (RADIOSITY_OT_bake, RADIOSITY_OT_clear, RADIOSITY_OT_show_colors)


def register():
    for c in CLASSES:
        bpy.utils.register_class(c)


def unregister():
    for c in reversed(CLASSES):
        bpy.utils.unregister_class(c)
