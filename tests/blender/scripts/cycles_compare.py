"""(b) Our bake of scenes.build_diffuse_scene() against the stored converged Cycles bake."""

import bpy
import numpy as np

import rt_common as rt
import scenes

ORDER = ("Floor", "Light", "Box")
ref_path = rt.arg("--ref")
rt.setup()
scenes.build_diffuse_scene()
bpy.context.scene.radiosity.preset = rt.arg("--preset", "HIGH")
ok, err, reports = rt.bake()
objs = [bpy.data.objects[n] for n in ORDER]
ours = np.concatenate([rt.corner_colors(o)[:, :3] for o in objs]) if ok else None
ref = np.load(ref_path)
out = {"ok": ok, "err": err, "reports": reports, "stats": rt.last_stats(),
       "fake": rt.native_is_fake()}
if ok:
    n_light = len(objs[1].data.loops)
    n_floor = len(objs[0].data.loops)
    emit = np.zeros(len(ref), bool)
    emit[n_floor:n_floor + n_light] = True

    def nrmse(x, r):
        return float(np.sqrt(np.mean((x - r) ** 2)) / np.sqrt(np.mean(r ** 2)))

    out["nrmse"] = nrmse(ours, ref)
    out["nrmse_no_emitter"] = nrmse(ours[~emit], ref[~emit])
    out["per_object"] = {}
    start = 0
    for o in objs:
        n = len(o.data.loops)
        out["per_object"][o.name] = {
            "nrmse": nrmse(ours[start:start + n], ref[start:start + n]),
            "ours_mean": ours[start:start + n].mean(axis=0).tolist(),
            "ref_mean": ref[start:start + n].mean(axis=0).tolist()}
        start += n
    out["shape_ok"] = ours.shape == ref.shape
rt.result(**out)
