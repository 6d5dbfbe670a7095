"""Live re-bake and cache hygiene.

depsgraph_update_post notices transform changes of baked objects (Object updates with
is_updated_transform whose matrix_world differs from the one at the last bake, so the echo of our
own colour writes — a Mesh update — never triggers), debounces with bpy.app.timers and re-bakes.
Timers never fire inside a blocking `blender -b --python` script, so `pump()` runs whatever is
pending synchronously; tests and scripts call it (``import radiosity; radiosity.pump()``).
load_post/undo_post drop every cache (the kept solution refers to data that no longer exists).
"""
import bpy
from bpy.app.handlers import persistent

from . import bake
from .core import job as core_job
from .core import live as core_live

TIMER_STEP = 0.1
last_errors = []        # messages of failed live re-bakes (no operator to report them to)


def _scene_by_key(key):
    for scene in bpy.data.scenes:
        if bake.scene_key(scene) == key:
            return scene
    return None


def _context_for(scene):
    """(view_layer, depsgraph) to bake `scene` with; the window's view layer when possible."""
    ctx = bpy.context
    try:
        if ctx.scene == scene and ctx.view_layer is not None:
            return ctx.view_layer, ctx.evaluated_depsgraph_get()
    except (AttributeError, RuntimeError):
        pass        # timers may run without a window context
    view_layer = scene.view_layers[0]
    return view_layer, view_layer.depsgraph


def _moved_objects(st, depsgraph):
    for upd in depsgraph.updates:
        if not upd.is_updated_transform or not isinstance(upd.id, bpy.types.Object):
            continue
        obj = upd.id.original
        if st.transforms.moved(obj.name_full, obj.matrix_world):
            return True
    return False


@persistent
def on_depsgraph_update(scene, depsgraph=None):
    props = getattr(scene, "radiosity", None)
    if props is None or not props.live:
        return
    st = core_live.state_for(bake.scene_key(scene))
    if st.busy:
        return          # inside our own bake/write
    if depsgraph is None:
        depsgraph = bpy.context.evaluated_depsgraph_get()
    if _moved_objects(st, depsgraph):
        st.request()
        if not bpy.app.timers.is_registered(_live_timer):
            bpy.app.timers.register(_live_timer, first_interval=core_live.DEBOUNCE_SECONDS)


def _finish_live(st, scene, run):
    try:
        run.finish()
    except bake.BakeError as exc:
        last_errors.append(str(exc))
    st.runs += 1


def _start_live(key, st, synchronous):
    """Begin (or with synchronous=True run to the end) a re-bake of scene `key`."""
    scene = _scene_by_key(key)
    if scene is None or not scene.radiosity.live:
        return
    st.take()
    view_layer, depsgraph = _context_for(scene)
    st.busy = True      # gathering evaluates the depsgraph: do not re-trigger ourselves
    try:
        run = bake.BakeRun(scene, view_layer, depsgraph, live=True).prepare()
    except bake.BakeError as exc:
        last_errors.append(str(exc))
        return
    finally:
        st.busy = False
    if synchronous:
        try:
            run.run_sync()
        except bake.BakeError as exc:
            last_errors.append(str(exc))
            return
        _finish_live(st, scene, run)
    else:
        run.job.start()
        st.job = run


def _step(synchronous):
    """Advance every scene's live state once; returns True while work remains."""
    busy = False
    for key, st in core_live.all_states().items():
        run = st.job
        if run is not None:
            if synchronous:
                try:
                    run.job.pump()
                except Exception:
                    pass
            else:
                run.job.poll()
            if run.job.state == core_job.RUNNING:
                busy = True
                continue
            st.job = None
            scene = _scene_by_key(key)
            if run.job.state == core_job.DONE and scene is not None:
                _finish_live(st, scene, run)
            elif run.job.state == core_job.FAILED:
                last_errors.append(f"solver failed: {run.job.error}")
            if st.pending:
                busy = True     # moved again while solving: go once more
            continue
        if st.pending and (synchronous or st.due()):
            _start_live(key, st, synchronous)
            busy = busy or st.job is not None or st.pending
        elif st.pending:
            busy = True
    return busy


def _live_timer():
    return TIMER_STEP if _step(synchronous=False) else None


def pump(timeout=None):
    """Run pending live re-bakes to completion now (headless scripts, tests). Returns runs."""
    import time
    deadline = None if timeout is None else time.monotonic() + timeout
    before = sum(st.runs for st in core_live.all_states().values())
    while _step(synchronous=True):
        if deadline is not None and time.monotonic() > deadline:
            break
    return sum(st.runs for st in core_live.all_states().values()) - before


def live_toggled(props, context):
    """Turning live on remembers nothing new; the last bake's matrices are the baseline."""
    if not props.live:
        st = core_live.all_states().get(bake.scene_key(context.scene))
        if st is not None:
            st.take()


def drop_caches():
    core_live.drop_all()
    core_job.cache_drop()


@persistent
def on_load_post(*_args):
    drop_caches()


@persistent
def on_undo_post(*_args):
    drop_caches()


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


def unregister():
    for hook, fn in _HOOKS:
        while fn in hook:
            hook.remove(fn)
    if bpy.app.timers.is_registered(_live_timer):
        bpy.app.timers.unregister(_live_timer)
    drop_caches()
