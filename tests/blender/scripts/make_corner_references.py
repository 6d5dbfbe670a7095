"""Converged Cycles references of the corner-exact tests (tests/blender/corner_scenes.py,
tests/blender/test_corner_exact.py). Needs no add-on.

    blender -b --factory-startup --python tests/blender/scripts/make_corner_references.py -- \
        --out tests/blender/data                     # Blender 3.4  -> corner_<case>_v3.*
    python3 tests/blender/scripts/make_corner_references.py -- --out tests/blender/data
                                                     # PyPI bpy 5.0 -> corner_<case>_v4.*
    options: --cases contact,lamp  --samples 16384  --threads 1

Per case and Blender generation (v3: 3.x, v4: 4.0 and later; area and spot light units and the
Principled BSDF differ between them, as for lights_*_v3/_v4) it bakes two independent halves of
samples/2 spp (Cycles seeds 1 and 2) and writes

  corner_<case>_<tag>.npy   float32 (2, corners, 3): [0] = (a + b) / 2, the samples-spp
                            reference; [1] = |a - b| / 2, its per-corner noise (the standard
                            deviation of a mean of two halves, estimated from their difference)
  corner_<case>_<tag>.json  settings: samples, seeds, threads, seconds per half, Blender version,
                            scene description, objects and their corner counts, noise summary.

For `factory` it also writes corner_factory_combined_<tag>.npy (same layout): the plain COMBINED
bake with glossy included (the cube's Principled BSDF has a specular layer the solver does not
model; the test's reference is the diffuse part, see test_corner_exact.py).

Cycles settings as NOTES.md: COMBINED bake to the active corner colour attribute, adaptive
sampling and denoising off, 64 bounces of every kind, no clamping; pass filter direct + indirect,
diffuse + emission (glossy and transmission off: the diffuse scenes do not change, the factory
cube's specular layer is left out).
"""
import json
import os
import sys

import bpy
import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
sys.path.insert(0, os.path.dirname(HERE))
import corner_scenes as cs  # noqa: E402
import cycles_ref  # noqa: E402
import rt_common as rt  # noqa: E402


def cycles_bake(objs, samples, seed, threads, glossy=False, name="CyclesRef"):
    scene = bpy.context.scene
    scene.render.engine = "CYCLES"
    scene.render.threads_mode = "FIXED"
    scene.render.threads = threads
    c = scene.cycles
    c.device = "CPU"
    c.samples = samples
    c.seed = seed
    c.use_animated_seed = False
    c.use_adaptive_sampling = False
    c.use_denoising = False
    c.max_bounces = c.diffuse_bounces = c.glossy_bounces = c.transmission_bounces = 64
    c.volume_bounces = c.transparent_max_bounces = 64
    c.sample_clamp_direct = c.sample_clamp_indirect = 0.0
    b = scene.render.bake
    b.target = "VERTEX_COLORS"
    b.use_pass_direct = b.use_pass_indirect = True
    b.use_pass_diffuse = b.use_pass_emit = True
    b.use_pass_glossy = glossy
    b.use_pass_transmission = False
    seconds = cycles_ref.bake_combined(objs, name)
    cols = np.concatenate([rt.corner_colors(o, name)[:, :3] for o in objs]).astype(np.float64)
    return cols, seconds


def two_halves(objs, samples, threads, glossy=False):
    half = samples // 2
    a, ta = cycles_bake(objs, half, 1, threads, glossy)
    b, tb = cycles_bake(objs, half, 2, threads, glossy)
    return np.stack([(a + b) / 2, np.abs(a - b) / 2]), [round(ta, 1), round(tb, 1)]


def noise_summary(stack, keep):
    r, n = stack[0][keep], stack[1][keep]
    floor = 0.05 * r.mean()
    rel = n / np.maximum(r, floor)
    return {"rrmse": float(np.sqrt(np.mean(rel ** 2))), "rel_p90": float(np.percentile(rel, 90)),
            "rel_max": float(rel.max()), "nrmse": float(np.sqrt(np.mean(n ** 2) / np.mean(r ** 2)))}


def main():
    samples = int(rt.arg("--samples", "16384"))
    threads = int(rt.arg("--threads", "1"))
    out = rt.arg("--out")
    tag = cs.version_tag()
    for case in rt.cases(cs.CASES):
        rt.reset()
        objs, info = cs.build(case)
        geo = cs.corner_geometry(objs, cs.EMITTERS.get(case, ()))
        stack, secs = two_halves(objs, samples, threads)
        path = os.path.join(out, f"corner_{case}_{tag}.npy")
        np.save(path, stack.astype(np.float32))
        meta = {"case": case, "tag": tag, "scene": cs.DESCRIPTION[case],
                "objects": list(cs.ORDER[case]),
                "corners": [len(o.data.loops) for o in objs],
                "emitters": list(cs.EMITTERS.get(case, ())),
                "samples": samples, "halves": [samples // 2, samples // 2], "seeds": [1, 2],
                "threads": threads, "seconds_per_half": secs,
                "blender": bpy.app.version_string,
                "cycles": "COMBINED to corner colour attribute; adaptive sampling and denoising "
                          "off; 64 bounces; no clamping; passes direct+indirect, diffuse+emit",
                "layout": "float32 (2, corners, 3): [0] mean of the halves, [1] |a-b|/2",
                "noise": noise_summary(stack, ~geo["emitter"])}
        if case == "factory":
            full, fsecs = two_halves(objs, samples, threads, glossy=True)
            np.save(os.path.join(out, f"corner_factory_combined_{tag}.npy"), full.astype(np.float32))
            meta["combined_with_glossy"] = {
                "file": f"corner_factory_combined_{tag}.npy", "seconds_per_half": fsecs,
                "mean_ratio_diffuse_over_combined": float(stack[0].mean() / full[0].mean())}
        with open(os.path.splitext(path)[0] + ".json", "w") as f:
            json.dump(meta, f, indent=1)
        print("made", path, json.dumps(meta), flush=True)
    print("RESULT " + json.dumps({"ok": True}))


main()
