"""(b) Our bake of scenes.build_diffuse_scene() against the stored converged Cycles bake.

Errors: bench/corner_metric.py (every corner but the emitter's, covered ones included: the floor
under the box and the box's bottom read 0 in Cycles; their share of the error apart)."""
import os
import sys

import bpy
import numpy as np

import rt_common as rt
import scenes

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "..", "bench"))
import corner_metric as cm  # noqa: E402

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
    # The scene's error (the headline figures) and, with the scene's floor, each object's.
    out["all"] = cm.corner_error(ours, ref, emitter=emit)
    out["nrmse"], out["rrmse"] = out["all"]["nrmse"], out["all"]["rrmse"]
    floor = cm.scene_floor(ref, emit)
    out["per_object"] = cm.per_object(ours, ref, [o.name for o in objs], [len(o.data.loops) for o in objs],
                                      emitter=emit, floor=floor)
    out["shape_ok"] = ours.shape == ref.shape
rt.result(**out)
