"""One bake, shared by the operator (sync and modal), the live re-bake and the batch tool.

    run = BakeRun(scene, view_layer, depsgraph, full=False)
    run.prepare()        # gather + validate + build native scene (or hit the cache)
    run.job.run() | run.job.start() + run.job.poll()/pump()
    run.finish()         # write every mesh, last_stats, transform cache

Errors raise BakeError (message names object and problem); nothing is written before finish().
"""
import os
import time

import numpy as np

from .core import baked
from .core import job as core_job
from .core import native_files, presets, session, srgb, stats
from .core.scene_data import InputError
from . import baked_state, gather, writer

STATS_KEY = "_last_stats"       # ID property behind the read-only scene.radiosity.last_stats
# (level, message) of the last bake, for scripts and tests: Blender prints operator reports but
# gives Python no way to read warnings back.
last_reports = []


class BakeError(Exception):
    pass


def load_native():
    try:
        from . import radiosity_native
    except ImportError as exc:
        # Names this Blender's Python and the Pythons the zip has a solver for.
        raise BakeError(native_files.load_error(os.path.dirname(__file__), exc)) from exc
    return radiosity_native


def scene_key(scene):
    return session.key_of(scene)


def set_last_stats(scene, data):
    scene.radiosity[STATS_KEY] = stats.to_json(data)


class BakeRun:
    def __init__(self, scene, view_layer, depsgraph, full=False, live=False):
        self.t0 = time.perf_counter()
        self.live = live
        self.scene, self.view_layer, self.depsgraph = scene, view_layer, depsgraph
        self.scene_name, self.view_layer_name = scene.name, view_layer.name
        self.full = full
        self.props = scene.radiosity
        self.warnings = []
        self.job = None
        self.matrices = {}
        self.no_emitter = False
        self.written = 0
        self.adaptive = []      # names of the adaptive-mesh objects written
        self.result = None

    def prepare(self):
        props = self.props
        if not props.attribute_name.strip():
            raise BakeError("the attribute name is empty")
        native = load_native()
        try:
            si, self.matrices, warnings = gather.gather(self.scene, self.view_layer,
                                                        self.depsgraph)
        except InputError as exc:       # NaN/inf in a matrix or material: names the object
            raise BakeError(str(exc)) from exc
        self.warnings.extend(warnings)
        si.lighting_only = bool(getattr(props, "lighting_only", False))
        si.adaptive_mesh = bool(getattr(props, "adaptive_mesh", False))
        if not si.objects:
            raise BakeError("nothing to bake: no visible, renderable mesh object with faces "
                            "in the view layer")
        if not any(o.target is not None for o in si.objects):
            # The operator reports only this error (no run to report warnings from), so the
            # reasons go into the message itself.
            why = "; ".join(w for w in warnings if any(f"'{n}'" in w for n in si.unwritable))
            raise BakeError("nothing to bake: no visible mesh object can receive colours"
                            + (f" ({why})" if why else ""))
        key = scene_key(self.scene)
        if self.full:
            session.forget_kept(key)
        try:
            settings = presets.make_settings(native, props.preset, props.error_threshold)
            # The output options are part of the key: a cached solution made for the other
            # output has the wrong values (or no leaf meshes).
            skey = presets.settings_key(props.preset, props.error_threshold) + \
                (("lighting_only",) if si.lighting_only else ()) + \
                (("adaptive_mesh",) if si.adaptive_mesh else ())
            self.no_emitter = not si.has_emitter()
            self.job = core_job.SolveJob(native, si, settings, skey, cache_key=key,
                                         use_cache=not self.full)
            if self.no_emitter:
                # Radiance is exactly zero everywhere: no solve needed, write zeros.
                self.warnings.append("the scene has no emitter (no emissive material): "
                                     "all colours are black")
                core_job.scene_data.validate(si)
                self.job.state = core_job.DONE
                self.job._radiance = [np.zeros((o.corner_count, 3), np.float32)
                                      for o in si.objects]
            else:
                self.job.prepare()
        except (InputError, ValueError) as exc:
            raise BakeError(str(exc)) from exc
        return self

    def run_sync(self):
        if self.job.state == core_job.IDLE:
            try:
                self.job.run()
            except (ValueError, RuntimeError) as exc:
                raise BakeError(f"solver failed: {exc}") from exc
        return self

    def _rebind(self):
        """An undo during the job may have re-read the scene at another address (its Python
        references then raise ReferenceError): find it again by name."""
        try:
            self.scene.name, self.view_layer.name
            return
        except ReferenceError:
            pass
        import bpy
        scene = bpy.data.scenes.get(self.scene_name)
        if scene is None:
            raise BakeError(f"the scene '{self.scene_name}' was removed during the bake")
        self.scene, self.props = scene, scene.radiosity
        self.view_layer = scene.view_layers.get(self.view_layer_name) or scene.view_layers[0]

    def finish(self):
        """Write all meshes (after the whole solve succeeded), then stats and caches."""
        self._rebind()
        native_stats = self.job.native_stats()
        for w in native_stats.get("warnings", None) or []:
            self.warnings.append(f"solver: {w}")
        byte_copy = bool(getattr(self.props, "byte_copy", False))
        try:
            items = self.job.rgba()
            byte_items = (self.job.srgb_bytes(float(self.props.exposure)) if byte_copy else None)
        except ValueError as exc:
            raise BakeError(str(exc)) from exc
        byte_name = srgb.byte_attribute_name(self.props.attribute_name)
        st = session.session(scene_key(self.scene)).live
        token = baked.new_token()
        st.busy = True          # our writes echo back through depsgraph_update_post
        try:
            self.written = writer.write_all(items, self.props.attribute_name, byte_items, byte_name,
                                            token)
            meshes = self.job.leaf_meshes() if self.job.scene_input.adaptive_mesh else None
            if meshes is not None:
                self.adaptive = writer.write_adaptive(self.job.scene_input.objects, meshes,
                                                      self.props.attribute_name)
        except RuntimeError as exc:
            raise BakeError(str(exc)) from exc
        finally:
            st.busy = False
        cached = self.job.is_cached
        mode = "full" if (cached or self.no_emitter) else self.job.mode
        extra = {"cached": cached, "preset": self.props.preset,
                 # Collection clusters (each instancing object adds one of its own).
                 "collections": len(self.job.scene_input.clusters)
                 - len(self.job.scene_input.instancers),
                 "written_objects": self.written, "report_warnings": len(self.warnings)}
        kept = self.job.kept()
        if cached and kept is not None and kept.bake_stats:
            # The colours are the kept solution's: say which bake made them (the panel shows
            # that bake, not a rewrite that solved nothing).
            extra["source"] = dict(kept.bake_stats)
        if self.no_emitter:
            extra["no_emitter"] = True
        elif mode == "full" and not cached and self.job.full_reason:
            extra["full_reason"] = self.job.full_reason
            if self.job.update_fallback:
                extra["update_fallback"] = self.job.update_fallback
        if mode == "incremental":
            extra.update(self.job.changes)
        if self.live:
            extra["live"] = True
        if self.adaptive:
            extra["adaptive_objects"] = list(self.adaptive)
        if self.job.scene_input.lighting_only:
            extra["lighting_only"] = True
        if byte_copy:
            extra["byte_copy"] = byte_name
            extra["exposure"] = float(self.props.exposure)
        si = self.job.scene_input
        extra["lights"] = len(si.lights)
        extra.update(getattr(si, "evaluation_stats", None) or {})
        if si.unwritable:
            # Took part in the solve (they cast and reflect light) but got no colours: linked
            # library data, Edit Mode, shared meshes (warnings say which reason).
            extra["unwritten_objects"] = list(si.unwritable)
        # What took part: objects of the view layer, instances (per instancing object), and
        # which of them only cast and reflect light (no colours of their own).
        extra["scene_objects"] = si.scene_objects
        extra["instances"] = si.instance_count
        extra["instancers"] = dict(si.instancers)
        extra["occluder_only"] = sorted(set(si.unwritable) | set(si.instancers))
        self.result = stats.make_stats(
            mode, time.perf_counter() - self.t0, native_stats,
            self.job.fallback_counts(), extra)
        set_last_stats(self.scene, self.result)
        if kept is not None and not cached:
            kept.bake_stats = stats.summary(self.result)
        baked_state.record(self.scene, token, self.matrices, self.result)
        baked_state.refresh(self.scene, self.view_layer)
        return self.result

    def cancel(self):
        if self.job is not None:
            self.job.cancel()


def bake_sync(scene, view_layer, depsgraph, full=False):
    """Whole bake, synchronous. Returns the finished BakeRun; raises BakeError."""
    run = BakeRun(scene, view_layer, depsgraph, full).prepare()
    run.run_sync()
    run.finish()
    return run
