"""Converged Cycles references of tex_world_scenes (test_textures_world.py).

    blender -b --factory-startup --python tests/blender/scripts/make_tex_world_references.py -- \
        --kind checker --samples 16384 --out tests/blender/data/tex_checker_v3.npy
    (bpy 5.0 / 5.2: python3 / python3.13 .../make_tex_world_references.py -- ... --out
    ..._v5_0.npy / ..._v5_2.npy, the tag blender_version.py gives; 16 s each here)

Writes the corner colours (RGB float32) of the scene's objects in tex_world_scenes.ORDER,
concatenated, and a .json beside it with the settings. Cycles as in shared/NOTES.md: COMBINED bake
to the active colour attribute, adaptive sampling and denoising off, 64 bounces, no clamping.
Needs no add-on.
"""
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import rt_common as rt  # noqa: E402
import tex_world_scenes as tws  # noqa: E402
from cycles_ref import reference_main  # noqa: E402


def build():
    kind = rt.arg("--kind")
    objs = tws.build(kind)
    return objs, {"scene": f"tex_world_scenes.build('{kind}')", "objects": [o.name for o in objs]}


reference_main("4096", build)
