"""Make or extend one scene's cached Cycles reference, inside Blender (started by run_refs.py).

    blender -b --factory-startup SCENE.blend --python bench/tradeoff/ref_scene.py -- \\
        --ref REF.npz [--ref-spp 16384] [--part-spp 4096] [--min-parts 2] [--zip Z]

Bakes independent parts (seeds 1, 2, ...) until the reference has --ref-spp samples in at least
--min-parts parts (bt_common.reference: an existing matching file is extended, never re-made),
then prints its noise figures. The add-on zip is only needed to read the emitters (the add-on's
own material reading) for the noise figures.
"""
import argparse
import os
import sys

import bpy

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import bt_common as bt  # noqa: E402


def main():
    p = argparse.ArgumentParser(prog="ref_scene.py")
    p.add_argument("--ref", required=True)
    p.add_argument("--zip", required=True)
    p.add_argument("--ref-spp", type=int, default=16384)
    p.add_argument("--part-spp", type=int, default=4096)
    p.add_argument("--min-parts", type=int, default=2)
    a = p.parse_args(bt.args())
    bt.install_addon(a.zip)
    scene = bpy.context.scene
    objs = bt.mesh_objects(scene)
    _, _, meta = bt.reference(a.ref, scene, objs, a.ref_spp, a.part_spp, a.min_parts)
    bt.result({"ok": True, "ref": a.ref, "samples": meta["samples"], "parts": meta["parts"],
               "noise": meta.get("noise")})


main()
