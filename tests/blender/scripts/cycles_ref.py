"""Converged Cycles bake to a corner colour attribute (NOTES.md settings), shared by the
reference generators of the light tests. Needs no add-on."""
import json
import os
import time

import bpy
import numpy as np

import rt_common as rt


def cycles_bake(objs, samples, name="CyclesRef", seed=1):
    scene = bpy.context.scene
    scene.render.engine = "CYCLES"
    c = scene.cycles
    c.device = "CPU"
    c.samples = samples
    c.use_adaptive_sampling = False      # otherwise it stops early
    c.use_denoising = False
    c.max_bounces = c.diffuse_bounces = 64
    c.glossy_bounces = c.transmission_bounces = c.volume_bounces = c.transparent_max_bounces = 64
    c.sample_clamp_direct = c.sample_clamp_indirect = 0.0
    c.seed = seed
    scene.render.bake.target = "VERTEX_COLORS"
    bake_combined(objs, name)
    return [rt.corner_colors(o, name)[:, :3].copy() for o in objs]


def bake_combined(objs, name):
    """COMBINED bake of `objs`, as the scene's Cycles settings stand, into a fresh corner colour
    attribute `name` of each. Returns the seconds the bake itself took."""
    for o in bpy.data.objects:
        o.select_set(False)
    for o in objs:
        rt.fresh_bake_target(o.data, name)
        o.select_set(True)
    bpy.context.view_layer.objects.active = objs[0]
    t = time.perf_counter()
    bpy.ops.object.bake(type="COMBINED")
    return time.perf_counter() - t


def save_reference(objs, samples, out, about, seconds_digits=None):
    """Bake `objs` (cycles_bake) and save the reference: their corners' RGB as float32,
    concatenated in the order of `objs`, at `out`, and beside it a .json of `about` (which
    scene) with each object's corner count, the samples, the seconds (rounded to
    `seconds_digits` if given) and the Blender version. Returns what the .json holds."""
    t = time.perf_counter()
    cols = cycles_bake(objs, samples)
    seconds = time.perf_counter() - t
    np.save(out, np.concatenate(cols).astype(np.float32))
    meta = dict(about, corners=[len(c) for c in cols], samples=samples,
                seconds=seconds if seconds_digits is None else round(seconds, seconds_digits),
                blender=bpy.app.version_string)
    with open(os.path.splitext(out)[0] + ".json", "w") as f:
        json.dump(meta, f, indent=1)
    return meta


def reference_main(default_samples, build):
    """A one-scene reference script: --samples (default `default_samples`) and --out from the
    command line, a fresh scene that `build()` makes (it returns the objects to bake and the
    .json's `about`), saved by save_reference; prints RESULT with what the .json holds."""
    samples = int(rt.arg("--samples", default_samples))
    out = rt.arg("--out")
    rt.reset()
    objs, about = build()
    meta = save_reference(objs, samples, out, about)
    print("RESULT " + json.dumps(meta))
