"""Converged Cycles references of tex_world_scenes (test_textures_world.py).

    blender -b --factory-startup --python tests/blender/scripts/make_tex_world_references.py -- \
        --kind checker --samples 4096 --out tests/blender/data/tex_checker_v3.npy
    (bpy 5.x: python3 .../make_tex_world_references.py -- ... --out ..._v4.npy)

Writes the corner colours (RGB float32) of the scene's objects in tex_world_scenes.ORDER,
concatenated, and a .json beside it with the settings. Cycles as in shared/NOTES.md: COMBINED bake
to the active colour attribute, adaptive sampling and denoising off, 64 bounces, no clamping.
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
import tex_world_scenes as tws  # noqa: E402


def main():
    kind = rt.arg("--kind")
    samples = int(rt.arg("--samples", "4096"))
    out = rt.arg("--out")
    rt.reset()
    objs = tws.build(kind)
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
        attr = o.data.color_attributes.new("CyclesRef", "FLOAT_COLOR", "CORNER")
        o.data.color_attributes.active_color = attr
        o.select_set(True)
    bpy.context.view_layer.objects.active = objs[0]
    t = time.perf_counter()
    bpy.ops.object.bake(type="COMBINED")
    seconds = time.perf_counter() - t
    cols = [rt.corner_colors(o, "CyclesRef")[:, :3].copy() for o in objs]
    np.save(out, np.concatenate(cols).astype(np.float32))
    meta = {"scene": f"tex_world_scenes.build('{kind}')", "objects": [o.name for o in objs],
            "corners": [len(x) for x in cols], "samples": samples, "seconds": seconds,
            "blender": bpy.app.version_string}
    with open(os.path.splitext(out)[0] + ".json", "w") as f:
        json.dump(meta, f, indent=1)
    print("RESULT " + json.dumps(meta))


main()
