"""(e) live drag: each step of a drag shows a preview at once (radiosity.preview_now(), what the
timer runs), the real update waits for the pause (radiosity.pump()) and equals a full bake."""
import time

import bpy
import numpy as np

import rt_common as rt
import scenes


def nrmse(x, y):
    return float(np.sqrt(np.mean((x - y) ** 2)) / np.sqrt(np.mean(y ** 2)))


def colours(objs):
    return np.concatenate([rt.corner_colors(o)[:, :3].copy() for o in objs])


mod = rt.setup()
objs = scenes.build_diffuse_scene()
scene = bpy.context.scene
scene.radiosity.live = True
ok, err, _ = rt.bake()
out = {"ok_first": ok, "fake": rt.native_is_fake()}
first = colours(objs)
box = bpy.data.objects["Box"]
bpy.context.view_layer.update()
states = lambda: list((x.live for x in mod.core.session.sessions().values()))  # noqa: E731
out["preview_pending_after_bake"] = any(st.preview_pending for st in states())
steps, shown, changes, seconds = 10, [], [], []
previous = first
for k in range(steps):
    t0 = time.perf_counter()
    m = box.matrix_world.copy()
    m.translation.x -= 0.08     # 0.8 m in all: off its footprint
    box.matrix_world = m
    bpy.context.view_layer.update()
    shown.append(mod.preview_now())
    seconds.append(time.perf_counter() - t0)
    now = colours(objs)
    changes.append(float(np.abs(now - previous).max()))
    previous = now
st = states()[0]
out["shown"] = shown
out["changes"] = changes
out["step_seconds"] = seconds
out["previews"] = st.previews
out["last_preview"] = st.last_preview
out["previewed"] = sorted(st.previewed)
out["update_pending"] = st.pending
out["runs_before_pump"] = st.runs
preview_last = previous
out["live_errors_before"] = list(mod.handlers.last_errors)
out["runs"] = mod.pump(timeout=600)
out["live_stats"] = rt.last_stats()
out["previewed_after_update"] = sorted(states()[0].previewed)
live_final = colours(objs)
ok2, _, _ = rt.bake(full=True)
full = colours(objs)
out["nrmse_update_full"] = nrmse(live_final, full)
out["nrmse_first_full"] = nrmse(first, full)
out["nrmse_preview_full"] = nrmse(preview_last, full)
out["live_errors"] = list(mod.handlers.last_errors)
# Live turned off right after a step was previewed: no update follows, so the bake's colours
# come back (never a preview left behind under the bake's name).
m = box.matrix_world.copy()
m.translation.x += 0.3
box.matrix_world = m
bpy.context.view_layer.update()
out["shown_before_off"] = mod.preview_now()
out["preview_differs"] = float(np.abs(colours(objs) - full).max())
scene.radiosity.live = False
out["after_live_off"] = float(np.abs(colours(objs) - full).max())
out["previewed_after_off"] = sorted(states()[0].previewed)
rt.result(ok=ok and ok2, **out)
