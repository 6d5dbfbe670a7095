"""Our bake of a scenes_rendered scene against its stored converged Cycles bake (issue 18).

Args: --scene NAME --ref PATH [--preset HIGH]. Errors as bench/corner_metric.py (every compared
corner; the emitter is not compared). Also reports what the bake did to the scene: attributes
of every mesh before/after (only the colour attribute may be added), the stats' object and
instance counts, the warnings."""
import os
import sys

import bpy
import numpy as np

import rt_common as rt
import scenes_rendered

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "..", "bench"))
import corner_metric as cm  # noqa: E402


def attribute_names():
    return {me.name: sorted(a.name for a in me.attributes) for me in bpy.data.meshes}


def modifier_state():
    return {o.name: [(m.name, m.type) for m in o.modifiers] for o in bpy.data.objects}


which = rt.arg("--scene")
ref_path = rt.arg("--ref")
rt.setup()
names, emitter = scenes_rendered.BUILDERS[which]()
bpy.context.scene.radiosity.preset = rt.arg("--preset", "HIGH")
before_attrs, before_mods = attribute_names(), modifier_state()
before_objects = sorted(o.name for o in bpy.data.objects)
ok, err, reports = rt.bake()
out = {"ok": ok, "err": err, "reports": reports, "stats": rt.last_stats(),
       "fake": rt.native_is_fake(), "names": names}
after_attrs = attribute_names()
out["added_attributes"] = {n: sorted(set(after_attrs[n]) - set(before_attrs.get(n, [])))
                           for n in after_attrs}
out["removed_attributes"] = {n: sorted(set(before_attrs[n]) - set(after_attrs.get(n, [])))
                             for n in before_attrs}
out["modifiers_unchanged"] = modifier_state() == before_mods
out["objects_unchanged"] = sorted(o.name for o in bpy.data.objects) == before_objects
if ok:
    objs = [bpy.data.objects[n] for n in names]
    cols = [rt.corner_colors(o) for o in objs]
    out["written"] = [c is not None for c in cols]
    if all(c is not None for c in cols):
        ours = np.concatenate([c[:, :3] for c in cols])
        ref = np.load(ref_path)
        out["shape_ok"] = ours.shape == ref.shape
        if out["shape_ok"]:
            out["all"] = cm.corner_error(ours, ref)
            floor = cm.scene_floor(ref)
            out["per_object"] = {}
            start = 0
            for o, c in zip(objs, cols):
                n = len(c)
                m = np.zeros(len(ref), bool)
                m[start:start + n] = True
                e = cm.corner_error(ours, ref, mask=m, floor=floor)
                out["per_object"][o.name] = {
                    **{k: e[k] for k in ("rrmse", "nrmse", "covered") if k in e},
                    "ours_mean": ours[start:start + n].mean(axis=0).tolist(),
                    "ref_mean": ref[start:start + n].mean(axis=0).tolist()}
                start += n
rt.result(**out)
