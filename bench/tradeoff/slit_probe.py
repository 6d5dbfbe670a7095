"""Probe for bench/results/closure_bias.md: the box room with its ceiling lamp lowered by DROP
(scene units, cm), baked by Cycles (COMBINED, SPP samples, seed 7) and by the add-on at MEDIUM;
corners, positions and owners to OUT.npz.

    blender -b --factory-startup example_blends/box_room.blend --python-exit-code 1 \
        --python bench/tradeoff/slit_probe.py -- DROP SPP OUT.npz
"""
import os
import sys

import bpy
import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import bt_common as bc  # noqa: E402

a = bc.args()
drop, spp, out = float(a[0]), int(a[1]), a[2]
bc.install_addon(os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "build", "radiosity.zip"))
scene = bpy.context.scene
lamp = bpy.data.objects["CeilingLight"]
lamp.location.z -= drop
bpy.context.view_layer.update()
objs = bc.mesh_objects(scene)
ref, sec, _ = bc.cycles_bake(scene, objs, spp, 7)
st, s2 = bc.our_bake(scene, "MEDIUM")
ours = bc.all_corners(objs, scene.radiosity.attribute_name)
pos = bc.corner_positions(objs)
own = bc.corner_owner(objs)
np.savez(out, ref=ref, ours=ours, pos=pos, own=own, names=np.array([o.name for o in objs]))
bc.result({"cycles_s": sec, "ours_s": s2})
