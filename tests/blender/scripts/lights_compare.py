"""Our bake of a light_scenes case against its stored converged Cycles reference.

    ... lights_compare.py -- --zip Z --tmp T --case point --data DIR [--preset HIGH]
"""
import os

import bpy
import numpy as np

import light_scenes
import rt_common as rt

case = rt.arg("--case")
data = rt.arg("--data")
rt.setup()
objs = light_scenes.build(case, box_collection=rt.arg("--box-in-scene") is None)
bpy.context.scene.radiosity.preset = rt.arg("--preset", "HIGH")
ok, err, reports = rt.bake()
out = {"ok": ok, "err": err, "reports": reports, "stats": rt.last_stats(), "fake": rt.native_is_fake(),
       "case": case, "tag": light_scenes.version_tag()}
ref_path = os.path.join(data, f"lights_{case}_{light_scenes.version_tag()}.npy")
out["have_ref"] = os.path.exists(ref_path)
if ok and out["have_ref"]:
    ours = np.concatenate([rt.corner_colors(o)[:, :3] for o in objs])
    ref = np.load(ref_path)
    out["shape_ok"] = ours.shape == ref.shape
    if out["shape_ok"]:
        def nrmse(x, r):
            return float(np.sqrt(np.mean((x - r) ** 2)) / np.sqrt(np.mean(r ** 2)))
        out["nrmse"] = nrmse(ours, ref)
        out["per_object"] = {}
        start = 0
        for o in objs:
            n = len(o.data.loops)
            out["per_object"][o.name] = {"nrmse": nrmse(ours[start:start + n], ref[start:start + n]),
                                         "ours_mean": ours[start:start + n].mean(axis=0).tolist(),
                                         "ref_mean": ref[start:start + n].mean(axis=0).tolist()}
            start += n
rt.result(**out)
if ok and out.get("shape_ok") and rt.arg("--per-face"):
    n_floor = len(objs[0].data.loops)
    b, r = ours[n_floor:], ref[n_floor:]
    names = ["-x", "+x", "-y", "+y", "-z", "+z"]
    print("PERFACE", {names[f]: (round(float(b[f*64:(f+1)*64].mean()), 4), round(float(r[f*64:(f+1)*64].mean()), 4)) for f in range(6)})
if ok and out.get("shape_ok") and rt.arg("--dump"):
    np.save(rt.arg("--dump"), np.stack([ours, ref]))
