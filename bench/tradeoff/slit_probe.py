"""Probe for bench/results/closure_bias.md: the box room with its ceiling lamp lowered by DROP
(scene units, cm), with DROP = "black:MATERIAL" that Diffuse material black, with DROP =
"bsdf" Cycles without light sampling of the lamp (a check of the reference), or with DROP =
"skirt" the 1 cm slit between the lamp and the ceiling closed
by a black band around the lamp's outline (the walls then cannot see the bright ceiling over the
lamp); baked by Cycles (COMBINED, SPP samples, seed 7) and by the add-on at MEDIUM; corners,
positions and owners to OUT.npz.

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
spp, out = int(a[1]), a[2]
bc.install_addon(os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "build", "radiosity.zip"))
scene = bpy.context.scene
lamp = bpy.data.objects["CeilingLight"]
if a[0] == "skirt":
    # Four vertical quads from the lamp's outline up to the ceiling, black diffuse.
    ws = [lamp.matrix_world @ v.co for v in lamp.data.vertices]
    lo = [min(w[k] for w in ws) for k in range(3)]
    hi = [max(w[k] for w in ws) for k in range(3)]
    z0, z1 = lo[2], lo[2] + 1.0
    c = [(lo[0], lo[1]), (hi[0], lo[1]), (hi[0], hi[1]), (lo[0], hi[1])]
    verts = [(x, y, z) for (x, y) in c for z in (z0, z1)]
    faces = [(2 * i, 2 * ((i + 1) % 4), 2 * ((i + 1) % 4) + 1, 2 * i + 1) for i in range(4)]
    me = bpy.data.meshes.new("Skirt")
    me.from_pydata(verts, [], faces)
    mat = bpy.data.materials.new("SkirtBlack")
    mat.use_nodes = True
    bsdf = next(n for n in mat.node_tree.nodes if n.type == "BSDF_PRINCIPLED")
    bsdf.inputs["Base Color"].default_value = (0, 0, 0, 1)
    me.materials.append(mat)
    skirt = bpy.data.objects.new("Skirt", me)
    scene.collection.objects.link(skirt)
elif a[0] == "bsdf":
    # Cycles without light sampling of the lamp (paths find it by BSDF sampling alone) and
    # without the light threshold: another estimator of the same scene, to check the reference.
    bc.bsdf_sampling_only(scene, [bpy.data.materials["CeilingLight"]])
elif a[0].startswith("black:"):
    # One material made black (Diffuse BSDF colour 0): what the rest gathers from it goes.
    node = next(n for n in bpy.data.materials[a[0][6:]].node_tree.nodes if n.type == "BSDF_DIFFUSE")
    node.inputs["Color"].default_value = (0, 0, 0, 1)
else:
    lamp.location.z -= float(a[0])
bpy.context.view_layer.update()
objs = bc.mesh_objects(scene)
ref, sec, _ = bc.cycles_bake(scene, objs, spp, 7)
st, s2 = bc.our_bake(scene, "MEDIUM")
ours = bc.all_corners(objs, scene.radiosity.attribute_name)
pos = bc.corner_positions(objs)
own = bc.corner_owner(objs)
np.savez(out, ref=ref, ours=ours, pos=pos, own=own, names=np.array([o.name for o in objs]))
bc.result({"cycles_s": sec, "ours_s": s2})
