"""Make the converged Cycles reference of scenes.build_diffuse_scene() (test (b)).

    blender -b --factory-startup --python tests/blender/scripts/make_cycles_reference.py -- \
        --samples 4096 --out tests/blender/data/diffuse_scene_cycles.npy

Writes the corner colours (RGB, float32) of Floor, Light, Box concatenated in that order, plus a
.json beside it with the settings used. Cycles settings follow shared/NOTES.md: COMBINED bake to
the active colour attribute, adaptive sampling and denoising off, 64 bounces, no clamping.
Needs no add-on.
"""
import json
import os
import sys
import time

import bpy
import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import rt_common as rt  # noqa: E402
import scenes  # noqa: E402

ORDER = ("Floor", "Light", "Box")


def cycles_bake(objs, samples, name="CyclesRef"):
    scene = bpy.context.scene
    scene.render.engine = "CYCLES"
    c = scene.cycles
    c.device = "CPU"
    c.samples = samples
    c.use_adaptive_sampling = False
    c.use_denoising = False
    c.max_bounces = c.diffuse_bounces = 64
    c.glossy_bounces = c.transmission_bounces = c.volume_bounces = c.transparent_max_bounces = 64
    c.sample_clamp_direct = c.sample_clamp_indirect = 0.0
    c.seed = 1
    scene.render.bake.target = "VERTEX_COLORS"
    for o in bpy.data.objects:
        o.select_set(False)
    for o in objs:
        me = o.data
        attr = me.color_attributes.new(name, "FLOAT_COLOR", "CORNER")
        me.color_attributes.active_color = attr
        o.select_set(True)
    bpy.context.view_layer.objects.active = objs[0]
    bpy.ops.object.bake(type="COMBINED")
    return [rt.corner_colors(o, name)[:, :3].copy() for o in objs]


def main():
    samples = int(rt.arg("--samples", "4096"))
    out = rt.arg("--out")
    rt.reset()
    scenes.build_diffuse_scene()
    objs = [bpy.data.objects[n] for n in ORDER]
    t = time.perf_counter()
    cols = cycles_bake(objs, samples)
    seconds = time.perf_counter() - t
    ref = np.concatenate(cols).astype(np.float32)
    np.save(out, ref)
    meta = {"scene": "scenes.build_diffuse_scene", "objects": list(ORDER),
            "corners": [len(c) for c in cols], "samples": samples, "seconds": seconds,
            "blender": bpy.app.version_string}
    with open(os.path.splitext(out)[0] + ".json", "w") as f:
        json.dump(meta, f, indent=1)
    print("RESULT " + json.dumps(meta))


main()
