"""Our bake of a light_scenes case against its stored converged Cycles reference.

    ... lights_compare.py -- --zip Z --tmp T --case point --data DIR [--preset HIGH]

Errors: bench/corner_metric.py (every corner, these scenes have no emitting mesh; covered
corners, under the box, included and their share of the error apart).
"""
import os
import sys

import bpy
import numpy as np

import light_scenes
import rt_common as rt

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "..", "bench"))
import corner_metric as cm  # noqa: E402

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
        out["all"] = cm.corner_error(ours, ref)
        out["nrmse"], out["rrmse"] = out["all"]["nrmse"], out["all"]["rrmse"]
        floor = cm.scene_floor(ref)
        out["per_object"] = cm.per_object(ours, ref, [o.name for o in objs], [len(o.data.loops) for o in objs],
                                          floor=floor)
rt.result(**out)
if ok and out.get("shape_ok") and rt.arg("--per-face"):
    n_floor = len(objs[0].data.loops)
    b, r = ours[n_floor:], ref[n_floor:]
    names = ["-x", "+x", "-y", "+y", "-z", "+z"]
    print("PERFACE", {names[f]: (round(float(b[f*64:(f+1)*64].mean()), 4), round(float(r[f*64:(f+1)*64].mean()), 4)) for f in range(6)})
if ok and out.get("shape_ok") and rt.arg("--dump"):
    np.save(rt.arg("--dump"), np.stack([ours, ref]))
