"""Make the converged Cycles reference of scenes.build_diffuse_scene() (test (b)).

    blender -b --factory-startup --python tests/blender/scripts/make_cycles_reference.py -- \
        --samples 4096 --out tests/blender/data/diffuse_scene_cycles.npy

Writes the corner colours (RGB, float32) of Floor, Light, Box concatenated in that order, plus a
.json beside it with the settings used. Cycles settings follow shared/NOTES.md: COMBINED bake to
the active colour attribute, adaptive sampling and denoising off, 64 bounces, no clamping.
Needs no add-on.
"""
import os
import sys

import bpy

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import scenes  # noqa: E402
from cycles_ref import reference_main  # noqa: E402

ORDER = ("Floor", "Light", "Box")


def build():
    scenes.build_diffuse_scene()
    return [bpy.data.objects[n] for n in ORDER], {"scene": "scenes.build_diffuse_scene",
                                                  "objects": list(ORDER)}


reference_main("4096", build)
