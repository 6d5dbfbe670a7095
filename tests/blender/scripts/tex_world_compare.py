"""Our bake of a tex_world_scenes scene against its stored converged Cycles bake (or, without
--ref, just the bake and what it left in bpy.data), for test_textures_world.py.

    ... tex_world_compare.py -- --zip build/radiosity.zip --kind checker|image|sky
        [--ref tests/blender/data/tex_checker_v3.npy] [--preset HIGH] [--dump OURS.npy]
"""
import os
import sys

import bpy
import numpy as np

import rt_common as rt
import tex_world_scenes as tws

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "..", "bench"))
import corner_metric as cm  # noqa: E402


def census():
    return {k: sorted(x.name for x in getattr(bpy.data, k))
            for k in ("scenes", "objects", "meshes", "materials", "images", "worlds", "cameras")}


kind = rt.arg("--kind")
ref_path = rt.arg("--ref")
if ref_path == "-":
    ref_path = None     # just bake (the caller picks the reference by out["ref_tag"])
rt.setup()
objs = tws.build(kind)
bpy.context.scene.radiosity.preset = rt.arg("--preset", "HIGH")
before = census()
attrs_before = {o.name: rt.color_attr_names(o) for o in objs}
ok, err, reports = rt.bake()
after = census()
out = {"ok": ok, "err": err, "reports": reports, "stats": rt.last_stats(),
       "fake": rt.native_is_fake(), "census_same": before == after,
       "census_diff": {k: [before[k], after[k]] for k in before if before[k] != after[k]},
       "attrs_added": {o.name: sorted(set(rt.color_attr_names(o)) - set(attrs_before[o.name]))
                       for o in objs}}
if ok:
    ours = np.concatenate([rt.corner_colors(o)[:, :3] for o in objs])
    out["means"] = {o.name: rt.corner_colors(o)[:, :3].mean(axis=0).tolist() for o in objs}
    if rt.arg("--dump", None):      # the corners, to study them (not used by the tests)
        np.save(rt.arg("--dump"), ours)
    if ref_path:
        ref = np.load(ref_path)
        out["shape_ok"] = ours.shape == ref.shape
        emit = np.zeros(len(ref), bool)
        start = 0
        for o in objs:
            n = len(o.data.loops)
            if o.name == "Light":
                emit[start:start + n] = True
            start += n
        if out["shape_ok"]:
            out["all"] = cm.corner_error(ours, ref, emitter=emit)
            floor = cm.scene_floor(ref, emit)
            out["per_object"] = cm.per_object(ours, ref, [o.name for o in objs],
                                              [len(o.data.loops) for o in objs], emitter=emit, floor=floor,
                                              keys=("rrmse", "nrmse"), skip=("Light",))
v = bpy.app.version
out["blender"] = bpy.app.version_string
out["ref_tag"] = "v3" if v < (4, 0, 0) else f"v{v[0]}_{v[1]}"
rt.result(**out)
