"""Converged Cycles references of the light tests (light_scenes.py), one per case and Blender
unit generation (v3: Blender 3.x, v4: 4.0 and later). Needs no add-on.

    blender -b --factory-startup --python tests/blender/scripts/make_light_references.py -- \
        --samples 8192 --out tests/blender/data            # Blender 3.4 -> lights_*_v3.npy
    python3 tests/blender/scripts/make_light_references.py -- --samples 8192 \
        --out tests/blender/data                           # PyPI bpy 5.0 -> lights_*_v4.npy

Cycles settings as NOTES.md: COMBINED to the active colour attribute, adaptive sampling and
denoising off, 64 bounces, no clamping. Writes <case>_<tag>.npy (Floor then Box corners, RGB
float32) and a .json with the settings and timing.
"""
import json
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import cycles_ref  # noqa: E402
import light_scenes  # noqa: E402
import rt_common as rt  # noqa: E402


def main():
    samples = int(rt.arg("--samples", "8192"))
    out = rt.arg("--out")
    tag = light_scenes.version_tag()
    for case in rt.cases(light_scenes.CASES):
        rt.reset()
        objs = light_scenes.build(case)
        path = os.path.join(out, f"lights_{case}_{tag}.npy")
        meta = cycles_ref.save_reference(objs, samples, path, {
            "case": case, "objects": list(light_scenes.ORDER)}, seconds_digits=1)
        print("made", path, meta, flush=True)
    print("RESULT " + json.dumps({"ok": True}))


main()
