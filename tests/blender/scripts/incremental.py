"""Incremental re-bake: move an object / change a light's strength, bake (full=False) and compare
with a full bake of the same scene. Also live mode: move + pump goes through the same path.

--scene diffuse (default: scenes.build_diffuse_scene) | blend (the file given with the harness's
blend=, e.g. example_blends/box_room.blend, using its scene["radiosity_move"]).
"""
import math
import os
import time

import bpy
import numpy as np

import rt_common as rt
import scenes

which = rt.arg("--scene", "diffuse")
preset = rt.arg("--preset", "MEDIUM")
if which == "diffuse":
    mod = rt.setup()
    scenes.build_diffuse_scene()
    moved_name, light_name = "Box", "Light"
    move = None
else:
    mod = rt.install_addon()
    f = rt.arg("--file")
    if f and os.path.abspath(bpy.data.filepath or "") != os.path.abspath(f):
        bpy.ops.wm.open_mainfile(filepath=f)
    move = dict(bpy.context.scene["radiosity_move"])
    moved_name, light_name = move["object"], "CeilingLight"
scene = bpy.context.scene
scene.radiosity.preset = preset
meshes = [o for o in scene.objects if o.type == "MESH"]


def colours():
    return {o.name: rt.corner_colors(o)[:, :3].copy() for o in meshes
            if rt.corner_colors(o) is not None}


def nrmse(a, b):
    x = np.concatenate([a[k] for k in sorted(b)])
    y = np.concatenate([b[k] for k in sorted(b)])
    return float(np.sqrt(np.mean((x - y) ** 2)) / np.sqrt(np.mean(y ** 2)))


def worst(a, b):
    """(object, NRMSE) of the worst object."""
    per = {k: float(np.sqrt(np.mean((a[k] - b[k]) ** 2)) / max(np.sqrt(np.mean(b[k] ** 2)), 1e-12))
           for k in b}
    k = max(per, key=per.get)
    return [k, per[k]]


def do_move(obj):
    if move is None:
        m = obj.matrix_world.copy()
        m.translation.x -= 0.7
        m.translation.y += 0.4
        obj.matrix_world = m
    else:
        obj.location = move["location"]
        obj.rotation_euler.z += math.radians(move.get("rotation_z_deg", 0.0))
    bpy.context.view_layer.update()


def set_strength(value):
    light = bpy.data.objects[light_name]
    for slot in light.material_slots:
        for n in slot.material.node_tree.nodes:
            if n.type == "EMISSION":
                n.inputs["Strength"].default_value = value


def rebake_and_compare(key):
    """After a change: an incremental bake, then a full one of the same scene; records both
    bakes' stats under `key` and `key`_full and how far the incremental colours are from the
    full ones. Returns the full bake's colours."""
    ok.append(rt.bake()[0])
    out[key] = rt.last_stats()
    inc = colours()
    ok.append(rt.bake(full=True)[0])
    out[key + "_full"] = rt.last_stats()
    full = colours()
    out[key + "_nrmse"] = nrmse(inc, full)
    out[key + "_worst"] = worst(inc, full)
    return full


out = {}
ok = []
t = time.perf_counter()
ok.append(rt.bake()[0])
out["first"] = rt.last_stats()
first = colours()

# 1) move -> incremental, compare with a full bake of the moved scene
do_move(bpy.data.objects[moved_name])
full = rebake_and_compare("move")
out["move_changed"] = nrmse(first, full)

# 2) light strength -> incremental
set_strength(4.0)
rebake_and_compare("light")

# 3) live: move + pump
scene.radiosity.live = True
obj = bpy.data.objects[moved_name]
obj.location.y -= (0.3 if move is None else 40.0)
bpy.context.view_layer.update()
out["live_runs"] = mod.pump(timeout=600)
out["live_errors"] = list(mod.handlers.last_errors)
out["live"] = rt.last_stats()
inc = colours()
scene.radiosity.live = False
ok.append(rt.bake(full=True)[0])
full = colours()
out["live_nrmse"] = nrmse(inc, full)
out["live_worst"] = worst(inc, full)
print("INCREMENTAL", {k: v for k, v in out.items() if "nrmse" in k or "worst" in k},
      {k: out[k]["seconds"] for k in ("first", "move", "move_full", "light", "light_full")})
rt.result(ok=ok, **out)
