"""Probe for bench/results/closure_bias.md: a Cycles reference of an example scene made without
light sampling of its emitting materials (paths find them by BSDF sampling alone; the light
threshold off), in parts with seeds 1..PARTS of SPP samples each; the corners of each part to
OUT.npz (`parts`, in bench/corner_metric.py's order: mesh objects by name, corners in order).

    blender -b --factory-startup example_blends/SCENE.blend --python-exit-code 1 \\
        --python bench/tradeoff/bsdf_ref.py -- SPP PARTS OUT.npz
"""
import os
import sys

import bpy
import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import bt_common as bc  # noqa: E402

a = bc.args()
spp, nparts, out = int(a[0]), int(a[1]), a[2]
mode = a[3] if len(a) > 3 else "bsdf"
scene = bpy.context.scene
if mode == "bsdf":
    bc.bsdf_sampling_only(scene, bpy.data.materials)
objs = bc.mesh_objects(scene)
parts, secs = [], []
for seed in range(1, nparts + 1):
    r, sec, _ = bc.cycles_bake(scene, objs, spp, seed)
    parts.append(r)
    secs.append(sec)
np.savez(out, parts=np.array(parts), names=np.array([o.name for o in objs]))
bc.result({"seconds": secs})
