"""Make the converged Cycles references of scenes_rendered (tests/blender/test_scene_as_rendered.py).

    blender -b --factory-startup --python tests/blender/scripts/make_rendered_reference.py -- \
        --scene subsurf --samples 16384 --out tests/blender/data/rendered_subsurf_cycles.npy

The modifiers scene bakes differently in 3.x and 5.x (Cycles takes the corner of the first
matching evaluated triangle, and Bevel's face order changed): make it with each,
rendered_modifiers_cycles_v3.npy with the 3.4 binary and _v5.npy with bpy 5.0 (python3 SCRIPT
-- ...).

Writes the corner colours (RGB, float32) of the scene's compared objects concatenated in order
(Cycles' bake to the original meshes' corners through its original-index mapping), plus a .json
beside it with the settings used. Cycles settings follow shared/NOTES.md
(tests/blender/scripts/cycles_ref.py). Needs no add-on.
"""
import os
import sys

import bpy

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import cycles_ref  # noqa: E402
import rt_common as rt  # noqa: E402
import scenes_rendered  # noqa: E402


def build():
    which = rt.arg("--scene")
    names, emitter = scenes_rendered.BUILDERS[which]()
    return ([bpy.data.objects[n] for n in names],
            {"scene": f"scenes_rendered.BUILDERS[{which!r}]", "objects": names})


cycles_ref.reference_main("16384", build)
