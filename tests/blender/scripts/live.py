"""(e) live: moving a baked object queues a re-bake; pumping it equals a full bake."""
import bpy
import numpy as np

import rt_common as rt
import scenes

mod = rt.setup()
objs = scenes.build_diffuse_scene()
scene = bpy.context.scene
scene.radiosity.live = True
ok, err, _ = rt.bake()
out = {"ok_first": ok}
first_floor = rt.corner_colors(objs[0]).copy()
box = bpy.data.objects["Box"]
# Our own colour write must not count as a move.
bpy.context.view_layer.update()
out["pending_after_bake"] = any(st.pending for st in (x.live for x in mod.core.session.sessions().values()))
# Move the box the way a script or the viewport would.
m = box.matrix_world.copy()
m.translation.x -= 0.7
box.matrix_world = m
bpy.context.view_layer.update()
out["pending_after_move"] = any(st.pending for st in (x.live for x in mod.core.session.sessions().values()))
out["runs"] = mod.pump(timeout=600)
out["live_errors"] = list(mod.handlers.last_errors)
out["live_stats"] = rt.last_stats()
live_vals = {o.name: rt.corner_colors(o).copy() for o in objs}
ok2, _, _ = rt.bake(full=True)
full_vals = {o.name: rt.corner_colors(o) for o in objs}
out["max_abs_diff"] = max(float(np.abs(live_vals[k] - full_vals[k]).max()) for k in live_vals)
x = np.concatenate([live_vals[k][:, :3] for k in sorted(live_vals)])
y = np.concatenate([full_vals[k][:, :3] for k in sorted(live_vals)])
out["nrmse"] = float(np.sqrt(np.mean((x - y) ** 2)) / np.sqrt(np.mean(y ** 2)))
out["floor_nrmse"] = float(np.sqrt(np.mean((live_vals["Floor"] - full_vals["Floor"]) ** 2))
                           / np.sqrt(np.mean(full_vals["Floor"] ** 2)))
out["changed_from_first"] = float(np.abs(live_vals["Floor"] - first_floor).max())
# With live off nothing is queued.
scene.radiosity.live = False
box.location.y += 0.3
bpy.context.view_layer.update()
out["pending_live_off"] = any(st.pending for st in (x.live for x in mod.core.session.sessions().values()))
out["runs_live_off"] = mod.pump(timeout=60)
rt.result(ok=ok and ok2, **out)
