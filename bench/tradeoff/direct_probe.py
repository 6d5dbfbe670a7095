"""Probe for bench/results/closure_bias.md: Cycles' direct light from the box room's ceiling lamp
at grazing angles, two estimators against ours. Every Diffuse material black but the walls'
(reflectance R, default 0.01, so that a wall corner holds R x its irradiance from the lamp alone,
give or take R² of bounces); Cycles baked (COMBINED, SPP samples, seed 7) with its default light
sampling, then without its light threshold, then also without light sampling of the lamp; the add-on at
MEDIUM. Corners, positions and owners to OUT.npz.

    blender -b --factory-startup example_blends/box_room.blend --python-exit-code 1 \\
        --python bench/tradeoff/direct_probe.py -- SPP OUT.npz [R]
"""
import os
import sys

import bpy
import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import bt_common as bc  # noqa: E402

a = bc.args()
spp, out = int(a[0]), a[1]
wall_rho = float(a[2]) if len(a) > 2 else 0.01
bc.install_addon(os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "build", "radiosity.zip"))
scene = bpy.context.scene
for mat in bpy.data.materials:
    if not mat.use_nodes:
        continue
    for node in mat.node_tree.nodes:
        if node.type == "BSDF_DIFFUSE":
            v = wall_rho if mat.name == "Wall" else 0.0
            node.inputs["Color"].default_value = (v, v, v, 1)
objs = bc.mesh_objects(scene)
light_sampled, sec1, _ = bc.cycles_bake(scene, objs, spp, 7)
threshold = scene.cycles.light_sampling_threshold
scene.cycles.light_sampling_threshold = 0.0
no_threshold, sec0, _ = bc.cycles_bake(scene, objs, spp, 7)
bc.bsdf_sampling_only(scene, [bpy.data.materials["CeilingLight"]])
bsdf_only, sec2, _ = bc.cycles_bake(scene, objs, spp, 7)
st, s3 = bc.our_bake(scene, "MEDIUM")
ours = bc.all_corners(objs, scene.radiosity.attribute_name)
np.savez(out, light_sampled=light_sampled, no_threshold=no_threshold, bsdf_only=bsdf_only, ours=ours, pos=bc.corner_positions(objs),
         own=bc.corner_owner(objs), names=np.array([o.name for o in objs]))
bc.result({"light_threshold": threshold, "cycles_light_sampled_s": sec1, "cycles_no_threshold_s": sec0, "cycles_bsdf_only_s": sec2, "ours_s": s3})
