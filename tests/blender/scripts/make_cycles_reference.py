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
from cycles_ref import cycles_bake  # noqa: E402

ORDER = ("Floor", "Light", "Box")


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
