"""Live re-bake, undo/redo and cache hygiene.

depsgraph_update_post notices transform changes of baked objects (Object updates with
is_updated_transform whose matrix_world differs from the bake the viewport shows, so the echo
of our own colour writes, a Mesh update, never triggers), debounces with bpy.app.timers and
re-bakes. Timers never fire inside a blocking `blender -b --python` script, so `pump()` runs
whatever is pending synchronously; tests and scripts call it (``import radiosity;
radiosity.pump()``).

While a drag goes on, each step is shown at once as a preview (core.preview: the kept solver
re-traces the direct light at the new placement, tens of milliseconds): the colours follow the
mouse, and the real update runs when the drag pauses: no move for a moment while the viewport
was free to take one (a draw handler tells when it draws), and, where Blender lists a window's
modal operators (4.2+), not while a Move, Rotate or Scale runs. `preview_now()` shows a pending step
synchronously (what the timer does; ``radiosity.preview_now()`` in scripts).

Undo and redo keep the kept solution: it is native state, valid whatever Blender re-reads, and
the next bake updates it incrementally to wherever undo put the objects. What they change is
which colours the meshes hold (baked_state judges that): out of date colours are re-baked with
Live on and flagged in the panel with Live off. Loading a file drops the kept solution (it
belongs to the scene that was closed).
"""
from collections import deque
import time
import traceback

import bpy
import numpy as np
from bpy.app.handlers import persistent

from . import bake, baked_state, eval_cache, writer
from .core import job as core_job
from .core import live as core_live
from .core import session
from .core import preview as core_preview
from .core import stats as core_stats

TIMER_STEP = 0.1
_draw_handle = []   # the 3D viewport's draw handler, while registered
# Messages of failed live re-bakes, newest last, for scripts (no operator reports them; the panel
# shows a scene's last one until a live update succeeds), and of the first failed preview of each
# drag. Bounded: the latest are kept.
last_errors = deque(maxlen=64)


def _report(st, message, trace=False):
    """A live failure of the scene whose live state is `st`: printed (with the exception's
    traceback when `trace`, for failures no one expected), kept in last_errors and shown in
    the scene's panel."""
    _log(message, trace)
    st.failed = message


def _log(message, trace=False):
    if trace:
        traceback.print_exc()
    print(f"Radiosity: {message}")
    last_errors.append(message)


def _preview_failed(st, message, trace=False):
    """A drag step the preview could not show: printed and kept in last_errors once per drag.
    Not shown in the panel: the update after the drag places the objects anyway and reports
    its own failure there (st.failed is the live re-bakes' to set and clear)."""
    if st.preview_failed(message):
        _log(message, trace)


def _live_states():
    """{scene key: live state} of every session."""
    return {key: s.live for key, s in session.sessions().items()}


def _scene_by_key(key):
    for scene in bpy.data.scenes:
        if bake.scene_key(scene) == key:
            return scene
    return None


def _view_layer_for(scene):
    """The window's view layer when it shows `scene`, else the scene's first one."""
    try:
        ctx = bpy.context
        if ctx.scene == scene and ctx.view_layer is not None:
            return ctx.view_layer
    except (AttributeError, RuntimeError):
        pass        # timers and handlers may run without a window context
    return scene.view_layers[0]


def _context_for(scene):
    """(view_layer, depsgraph) to bake `scene` with; the window's view layer when possible."""
    ctx = bpy.context
    try:
        if ctx.scene == scene and ctx.view_layer is not None:
            return ctx.view_layer, ctx.evaluated_depsgraph_get()
    except (AttributeError, RuntimeError):
        pass
    view_layer = scene.view_layers[0]
    return view_layer, view_layer.depsgraph


# -- what the user sees while a live re-bake runs ----------------------------------------------
def _windows():
    wm = getattr(bpy.context, "window_manager", None)
    return list(wm.windows) if wm is not None else []


def _status(text):
    """Status bar text in every window (None clears it); a live job has no operator to own it."""
    for win in _windows():
        try:
            with bpy.context.temp_override(window=win):
                win.workspace.status_text_set(text)
        except (AttributeError, RuntimeError, TypeError):
            pass    # a window closing, or a Blender without temp_override: the panel still shows it


def redraw():
    """Panels read module state, which Blender does not watch: ask for a redraw."""
    for win in _windows():
        for area in win.screen.areas:
            if area.type in ("VIEW_3D", "PROPERTIES"):
                area.tag_redraw()


def live_status_text(st, now=None):
    """Status bar text of a running live re-bake (shown with its progress and time so far)."""
    now = time.monotonic() if now is None else now
    elapsed = now - (st.job_started or now)
    return (f"Radiosity: live update after a move… {st.progress * 100:.0f} %   "
            f"{elapsed:.0f} s")


# -- live re-bake ------------------------------------------------------------------------------
def _queue(st):
    st.request()
    if not bpy.app.timers.is_registered(_live_timer):
        bpy.app.timers.register(_live_timer, first_interval=core_live.DEBOUNCE_SECONDS)


@persistent
def on_depsgraph_update(scene, depsgraph=None):
    props = getattr(scene, "radiosity", None)
    if props is None:
        return
    st = session.session(bake.scene_key(scene)).live
    if st.busy:
        return          # inside our own bake/write
    if st.unjudged:
        settle(scene)   # the first evaluation after a load or an undo: matrices are right now
    if depsgraph is None:
        depsgraph = bpy.context.evaluated_depsgraph_get()
    was = st.stale
    rebake = False
    for upd in depsgraph.updates:
        if not upd.is_updated_transform or not isinstance(upd.id, bpy.types.Object):
            continue
        obj = upd.id.original
        st.track(obj.name_full, obj.matrix_world)
        rebake = rebake or st.needs_rebake(obj.name_full, obj.matrix_world)
    if rebake and props.live:
        _queue(st)
        _queue_preview(st)
    if st.stale != was:
        redraw()


# -- the drag's preview ------------------------------------------------------------------------
PREVIEW_STATUS = "Radiosity: live preview (direct light); full update when the drag pauses"


def _queue_preview(st):
    st.preview_pending = True
    if not bpy.app.timers.is_registered(_preview_timer):
        bpy.app.timers.register(_preview_timer, first_interval=0.0)


def _preview_timer():
    preview_now()
    return None


def preview_now():
    """Show every scene's pending drag step now; returns how many previews were written. A
    scene whose live update is running keeps its step pending (the solver is busy; the update
    that follows shows the place anyway); so does one whose matrices are not judged yet after
    an undo or a load (re-read objects read identity until the depsgraph evaluates them)."""
    shown = 0
    for key, st in _live_states().items():
        if not st.preview_pending:
            continue
        if st.job is not None or st.unjudged:
            st.preview_skipped = ("a live update is running" if st.job is not None
                                  else "the scene is being judged again after an undo or a load")
            continue
        st.preview_pending = False
        scene = _scene_by_key(key)
        if scene is not None and scene.radiosity.live and _preview(key, st, scene):
            shown += 1
    return shown


def _preview(key, st, scene):
    """One preview of `scene` where its objects stand now; never raises (a step it cannot
    show is left to the update after the drag, LiveState.preview_skipped says why, and a
    failure is reported once per drag)."""
    entry = session.kept(key)
    why = core_preview.unavailable(entry)
    if why:
        st.preview_skipped = why
        return False
    t0 = time.perf_counter()
    try:
        matrices = {}
        for name in entry.names:
            obj = bpy.data.objects.get(name)
            if obj is not None:
                matrices[name] = np.array(obj.matrix_world, dtype=np.float64)
        changed, counts = core_preview.radiance(entry, matrices)
        # Objects an earlier step changed and this one does not: back to the bake's colours.
        writes = dict(changed)
        for name in st.previewed - set(changed):
            base = core_preview.base_radiance(entry, name)
            if base is not None:
                writes[name] = base
        written = _write_preview(scene, entry, st, writes)
    except (RuntimeError, ValueError) as exc:
        # A matrix the solver refuses (the update after the drag says why), a solver that
        # started a job meanwhile, colours it could not convert.
        _preview_failed(st, f"preview failed: {exc}")
        return False
    except Exception as exc:        # a timer must not raise (Blender would drop it)
        _preview_failed(st, f"preview failed: {exc!r}", trace=True)
        return False
    st.previewed = set(changed) & written
    st.preview_skipped = None
    st.previews += 1
    st.last_preview = dict(counts, objects=len(written), seconds=time.perf_counter() - t0)
    _status(PREVIEW_STATUS)
    redraw()
    return True


def _write_preview(scene, entry, st, writes):
    """{name: radiance} into the meshes' colour attribute (only that); returns the names
    written. Everything is converted before the first mesh is touched."""
    attribute = scene.radiosity.attribute_name
    items = []
    for name, rad in writes.items():
        rgba = core_preview.rgba_for(entry, name, rad)
        me = writer.resolve(entry.outputs[name]["target"]) if rgba is not None else None
        if me is None or len(me.loops) * 4 != len(rgba):
            continue    # no colours of its own, or deleted or re-shaped since the bake
        items.append((name, me, rgba))
    st.busy = True      # our writes echo back through depsgraph_update_post
    try:
        for _name, me, rgba in items:
            writer.write_mesh(me, attribute, rgba)
    finally:
        st.busy = False
    return {name for name, _me, _rgba in items}


def _drop_preview(key, st):
    """No update follows the preview shown (Live turned off, a failed update): the meshes go
    back to the kept solution's colours and the status bar clears."""
    st.preview_pending = False
    if st.previewed:
        entry = session.kept(key)
        scene = _scene_by_key(key)
        if entry is not None and scene is not None:
            writes = {n: core_preview.base_radiance(entry, n) for n in st.previewed}
            try:
                _write_preview(scene, entry, st, {n: r for n, r in writes.items() if r is not None})
            except Exception as exc:    # noqa: BLE001 (a handler must not raise)
                _report(st, f"could not put the baked colours back: {exc!r}", trace=True)
        st.previewed = set()
    _status(None)


def _finish_live(st, scene, run):
    ok = False
    try:
        run.finish()
        ok = True
    except bake.BakeError as exc:
        _report(st, str(exc))
    except Exception as exc:
        # Printed, kept, and not raised: an exception would unregister the live timer and
        # leave the job in place, so Live would stop for the rest of the session.
        _report(st, f"live re-bake failed: {exc!r}", trace=True)
    st.runs += 1
    if ok:
        st.previewed = set()    # the update wrote every mesh
        st.failed = None
    else:
        _drop_preview(bake.scene_key(scene), st)


def _start_live(key, st, synchronous):
    """Begin (or with synchronous=True run to the end) a re-bake of scene `key`."""
    scene = _scene_by_key(key)
    if scene is None or not scene.radiosity.live:
        return
    if st.preview_pending and not synchronous:
        # A step the preview timer has not shown yet (a busy main thread runs both timers at
        # once, this one first): shown before the update takes the solver for seconds.
        st.preview_pending = False
        _preview(key, st, scene)
    st.take()
    view_layer, depsgraph = _context_for(scene)
    st.busy = True      # gathering evaluates the depsgraph: do not re-trigger ourselves
    try:
        run = bake.BakeRun(scene, view_layer, depsgraph, live=True).prepare()
    except bake.BakeError as exc:
        _report(st, str(exc))
        _drop_preview(key, st)
        return
    finally:
        st.busy = False
    if synchronous:
        try:
            run.run_sync()
        except bake.BakeError as exc:
            _report(st, str(exc))
            _drop_preview(key, st)
            return
        _finish_live(st, scene, run)
    else:
        run.job.start()
        st.job, st.job_started, st.progress = run, time.monotonic(), 0.0
        _status(live_status_text(st))
        redraw()


def _step(synchronous):
    """Advance every scene's live state once; returns True while work remains."""
    busy = False
    for key, st in _live_states().items():
        run = st.job
        if run is not None:
            if synchronous:
                try:
                    run.job.pump()
                except Exception as exc:    # noqa: BLE001 (a handler must not raise)
                    if run.job.state != core_job.FAILED:    # a failed solve is reported below
                        _report(st, f"live re-bake failed while solving: {exc!r}", trace=True)
            else:
                st.progress = run.job.poll()
            if run.job.state == core_job.RUNNING:
                if not synchronous:
                    _status(live_status_text(st))
                    redraw()
                busy = True
                continue
            st.job = st.job_started = None
            scene = _scene_by_key(key)
            if run.job.state == core_job.DONE and scene is not None:
                _finish_live(st, scene, run)
            elif run.job.state == core_job.FAILED:
                _report(st, f"solver failed: {run.job.error}")
                _drop_preview(key, st)
            if not synchronous:
                _status(None)
                redraw()
            if st.pending:
                busy = True     # moved again while solving: go once more
            continue
        if st.pending and (synchronous or (st.due() and not _transforming())):
            _start_live(key, st, synchronous)
            busy = busy or st.job is not None or st.pending
        elif st.pending:
            busy = True
    return busy


def _transforming():
    """Whether a Move, Rotate or Scale operator is running in a window (Blender before 4.2
    lists no modal operators: False there, and the pause alone decides)."""
    for win in _windows():
        for op in getattr(win, "modal_operators", ()):
            if op.bl_idname.startswith("TRANSFORM_OT_"):
                return True
    return False


def _viewport_drawn():
    for st in _live_states().values():
        st.drawn()


def _live_timer():
    return TIMER_STEP if _step(synchronous=False) else None


def pump(timeout=None):
    """Run pending live re-bakes to completion now (headless scripts, tests). Returns runs."""
    deadline = None if timeout is None else time.monotonic() + timeout
    before = sum(st.runs for st in _live_states().values())
    while _step(synchronous=True):
        if deadline is not None and time.monotonic() > deadline:
            break
    return sum(st.runs for st in _live_states().values()) - before


def live_toggled(props, context):
    """Off: drop a queued re-bake. On: bring an out-of-date bake up to date (moves made while
    Live was off count); a scene never baked stays unbaked."""
    st = settle(context.scene)
    if not props.live:
        st.take()
        _drop_preview(bake.scene_key(context.scene), st)
    elif st.shown.baked and st.stale:
        _queue(st)


# -- undo, redo, load --------------------------------------------------------------------------
def _rekey():
    """Scene keys carry the scene's address; should undo have re-read a scene elsewhere, carry
    its kept solution, live state and records over by name (never lose a bake to undo)."""
    current = {bake.scene_key(s) for s in bpy.data.scenes}
    by_name = {}
    for s in bpy.data.scenes:
        by_name.setdefault(s.name_full, []).append(bake.scene_key(s))
    for old in set(session.sessions()) - current:
        new = by_name.get(old.rsplit("@", 1)[0], [])
        if len(new) == 1:
            session.rekey(old, new[0])


def settle(scene, writes=True):
    """Judge again, after a load or an undo, which bake the meshes of `scene` show; returns its
    live state. After an undo, last_stats follows the bake shown and, with Live on, an
    out-of-date bake is re-baked (writes=False, from a panel's draw, leaves that to the
    handlers: drawing may not write)."""
    st = session.session(bake.scene_key(scene)).live
    why = st.unjudged
    if not why or (why == "undo" and not writes):
        return st
    baked_state.refresh(scene, _view_layer_for(scene))
    if why != "undo":
        return st
    props = scene.radiosity
    record = st.shown.record
    if record is not None and record.stats:
        # last_stats describes the colours shown: undo may have kept the stats of a later
        # bake (a scene Blender did not re-read) while the meshes went back.
        text = core_stats.to_json(record.stats)
        if props.last_stats != text:
            bake.set_last_stats(scene, record.stats)
    if props.live and st.shown.baked and (st.stale or st.job is not None):
        _queue(st)
    redraw()
    return st


def _settle_all():
    try:
        bpy.context.evaluated_depsgraph_get()      # matrices of re-read objects, evaluated
    except (AttributeError, RuntimeError):
        pass
    for scene in bpy.data.scenes:
        if getattr(scene, "radiosity", None) is not None:
            settle(scene)
    return None


def _unjudge(why):
    for scene in bpy.data.scenes:
        if getattr(scene, "radiosity", None) is not None:
            session.session(bake.scene_key(scene)).live.unjudged = why
    # The depsgraph evaluation that follows settles each scene (on_depsgraph_update); this
    # timer settles any the evaluation did not report.
    if not bpy.app.timers.is_registered(_settle_all):
        bpy.app.timers.register(_settle_all, first_interval=0.2)


@persistent
def on_undo_post(*_args):
    """After undo or redo: judge which bake the meshes show now (once the depsgraph has been
    evaluated). With Live on an out-of-date bake is re-baked, incrementally from the kept
    solution; a live job still running solves what the scene was before the undo, so it is
    followed by another."""
    _rekey()
    for st in _live_states().values():
        # Undo put back the meshes' colours of its step: no preview of ours is shown any more.
        st.preview_pending = False
        st.previewed = set()
    _unjudge("undo")


def drop_caches():
    session.drop_all()
    eval_cache.clear()      # textures and worlds Cycles evaluated (keyed by content)


@persistent
def on_load_post(*_args):
    drop_caches()
    _unjudge("load")


_HOOKS = (
    (bpy.app.handlers.depsgraph_update_post, on_depsgraph_update),
    (bpy.app.handlers.load_post, on_load_post),
    (bpy.app.handlers.undo_post, on_undo_post),
    (bpy.app.handlers.redo_post, on_undo_post),
)


def register():
    for hook, fn in _HOOKS:
        if fn not in hook:
            hook.append(fn)
    if not _draw_handle:
        _draw_handle.append(bpy.types.SpaceView3D.draw_handler_add(_viewport_drawn, (), "WINDOW", "POST_PIXEL"))


def unregister():
    for hook, fn in _HOOKS:
        while fn in hook:
            hook.remove(fn)
    while _draw_handle:
        bpy.types.SpaceView3D.draw_handler_remove(_draw_handle.pop(), "WINDOW")
    for timer in (_live_timer, _settle_all, _preview_timer):
        if bpy.app.timers.is_registered(timer):
            bpy.app.timers.unregister(timer)
    _status(None)
    drop_caches()
