"""Incremental re-bake of a light change against a full bake of the same scene.

--case point: move the point light; --case area_square: dim the area light (power x 0.3).
"""
import bpy
import numpy as np

import light_scenes
import rt_common as rt

case = rt.arg("--case", "point")
rt.setup()
objs = light_scenes.build(case)
scene = bpy.context.scene
scene.radiosity.preset = rt.arg("--preset", "HIGH")


def colours():
    return np.concatenate([rt.corner_colors(o)[:, :3] for o in objs]).copy()


def nrmse(x, r):
    return float(np.sqrt(np.mean((x - r) ** 2)) / np.sqrt(np.mean(r ** 2)))


oks = []
ok, err, _ = rt.bake()
oks.append(ok)
first = rt.last_stats()
before = colours()
light = bpy.data.objects[case]
if case == "point":
    light.location = (0.9, -0.6, 1.3)
else:
    light.data.energy *= 0.3
bpy.context.view_layer.update()
ok, err2, _ = rt.bake(full=False)
oks.append(ok)
inc = rt.last_stats()
inc_cols = colours()
ok, err3, _ = rt.bake(full=True)
oks.append(ok)
full = rt.last_stats()
full_cols = colours()
n_floor = len(objs[0].data.loops)
per_object = {"Floor": nrmse(inc_cols[:n_floor], full_cols[:n_floor]),
              "Box": nrmse(inc_cols[n_floor:], full_cols[n_floor:])}
if rt.arg("--dump"):
    np.save(rt.arg("--dump"), np.stack([inc_cols, full_cols]))
rt.result(per_object=per_object, ok=oks, err=[err, err2, err3], fake=rt.native_is_fake(), first=first, inc=inc, full=full,
          nrmse=nrmse(inc_cols, full_cols), changed=nrmse(before, full_cols))
