"""Incremental re-bake of the instances scene (scenes_rendered.build_instances): moving the
Empty that instances a collection moves its instances (an incremental move of each); the live
re-bake sees the Empty move; changing the geometry-nodes point count adds an instance. Each
update is compared with a full bake of the same state (NRMSE over the written corners)."""
import bpy
import numpy as np

import rt_common as rt
import scenes_rendered

mod = rt.setup()
names, _ = scenes_rendered.build_instances()
scene = bpy.context.scene
scene.radiosity.preset = rt.arg("--preset", "MEDIUM")
out = {"ok": []}


def colours():
    return np.concatenate([rt.corner_colors(bpy.data.objects[n])[:, :3] for n in names])


def step(label, **kw):
    ok, err, reports = rt.bake(**kw)
    out["ok"].append(ok)
    st = rt.last_stats() or {}
    out[label] = {k: st.get(k) for k in ("mode", "moved", "added", "removed", "replaced",
                                          "instances", "full_reason", "live")}
    return colours() if ok else None


def nrmse(a, b):
    return float(np.sqrt(np.mean((a - b) ** 2)) / np.sqrt(np.mean(b ** 2)))


first = step("first")
out["fake"] = rt.native_is_fake()
inst = bpy.data.objects[rt.arg("--move", "CrateInstance")]
inst.location.x += 0.9
inst.location.y += 0.5
moved = step("move")
full = step("move_full", full=True)
out["move_nrmse"], out["move_changed"] = nrmse(moved, full), nrmse(first, full)
# Live: the Empty moves back, the depsgraph handler queues a re-bake, pump runs it.
scene.radiosity.live = True
inst.location.x -= 0.9
bpy.context.view_layer.update()
mod.pump()
out["live_runs"] = mod.core.session.session(mod.bake.scene_key(scene)).live.runs
st = rt.last_stats() or {}
out["live"] = {k: st.get(k) for k in ("mode", "moved", "live")}
scene.radiosity.live = False
live = colours()
out["live_nrmse"] = nrmse(live, step("live_full", full=True))
# One more point on the geometry-nodes line: one instance more.
line = next(n for n in bpy.data.node_groups["Scatter"].nodes if n.bl_idname == "GeometryNodeMeshLine")
line.inputs["Count"].default_value = 4
added = step("add")
out["add_nrmse"] = nrmse(added, step("add_full", full=True))
rt.result(**out)
