"""Measure Cycles' light unit conversions (no add-on needed).

    blender -b --factory-startup --python tests/blender/scripts/measure_light_units.py -- \
        --samples 1024 --out /tmp/units.json

One scene per case: a lone 4x4 m floor (10x10 quads, Diffuse 0.5, black world: no
interreflection, so a COMBINED bake is exactly rho * E / pi) lit by one light. Writes the floor's
corner colours with the corner positions; light_units.py (tests/python) compares them with the
analytic irradiance of each candidate conversion.
"""
import json
import math
import os
import sys

import bpy
import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import rt_common as rt  # noqa: E402
import cycles_ref  # noqa: E402

CASES = {
    # name: (type, settings, location, rotation_euler)
    "point": ("POINT", {"energy": 100.0, "shadow_soft_size": 0.05}, (0.3, -0.2, 1.5), (0, 0, 0)),
    "point_r": ("POINT", {"energy": 100.0, "shadow_soft_size": 0.5}, (0.3, -0.2, 1.5), (0, 0, 0)),
    "point_diffuse": ("POINT", {"energy": 100.0, "shadow_soft_size": 0.05, "diffuse_factor": 0.5},
                      (0.3, -0.2, 1.5), (0, 0, 0)),
    "spot": ("SPOT", {"energy": 100.0, "shadow_soft_size": 0.05, "spot_size": math.radians(90),
                      "spot_blend": 0.0}, (0.0, 0.0, 1.0), (0, 0, 0)),
    "spot_blend": ("SPOT", {"energy": 100.0, "shadow_soft_size": 0.05, "spot_size": math.radians(90),
                            "spot_blend": 0.5}, (0.0, 0.0, 1.0), (0, 0, 0)),
    "sun": ("SUN", {"energy": 2.0, "angle": math.radians(1.0)}, (0, 0, 3), (math.radians(30), 0, 0)),
    "area_square": ("AREA", {"energy": 100.0, "shape": "SQUARE", "size": 1.0}, (0, 0, 1.0), (0, 0, 0)),
    "area_rect": ("AREA", {"energy": 100.0, "shape": "RECTANGLE", "size": 1.0, "size_y": 0.5},
                  (0, 0, 1.0), (0, 0, 0)),
    "area_disk": ("AREA", {"energy": 100.0, "shape": "DISK", "size": 1.0}, (0, 0, 1.0), (0, 0, 0)),
    "world": (None, {"color": (0.4, 0.5, 0.7), "strength": 1.5}, None, None),
}


def build(case):
    rt.reset()
    rt.black_world()
    floor_mat = rt.diffuse_material("Floor", (0.5, 0.5, 0.5))
    verts, faces = rt.grid((-2, -2, 0), (4, 0, 0), (0, 4, 0), 10)
    floor = rt.mesh_object("Floor", verts, faces, None, floor_mat)
    kind, settings, loc, rot = CASES[case]
    if kind is None:
        bg = bpy.context.scene.world.node_tree.nodes["Background"]
        bg.inputs["Color"].default_value = (*settings["color"], 1.0)
        bg.inputs["Strength"].default_value = settings["strength"]
    else:
        light = bpy.data.lights.new(case, kind)
        for k, v in settings.items():
            setattr(light, k, v)
        obj = bpy.data.objects.new(case, light)
        obj.location = loc
        obj.rotation_euler = rot
        rt.link(obj)
    return floor


def main():
    samples = int(rt.arg("--samples", "1024"))
    out = rt.arg("--out")
    data = {"blender": bpy.app.version_string, "samples": samples, "cases": {}}
    for case in rt.cases(CASES):
        floor = build(case)
        col = cycles_ref.cycles_bake([floor], samples)[0]
        me = floor.data
        cv = np.empty(len(me.loops), np.int32)
        me.loops.foreach_get("vertex_index", cv)
        co = np.empty(len(me.vertices) * 3, np.float32)
        me.vertices.foreach_get("co", co)
        pos = co.reshape(-1, 3)[cv]
        data["cases"][case] = {"pos": pos.tolist(), "rgb": col.tolist()}
        print("case", case, "mean", col.mean(axis=0), flush=True)
    with open(out, "w") as f:
        json.dump(data, f)
    print("RESULT " + json.dumps({"ok": True}))


main()
