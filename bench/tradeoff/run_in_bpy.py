"""Run a bench/tradeoff Blender script in the PyPI bpy module (Blender 5.x): opens the .blend,
then runs the script with the arguments after it.

    python3 bench/tradeoff/run_in_bpy.py -- SCENE.blend SCRIPT.py [ARGS ...]
"""
import runpy
import sys

import bpy

args = sys.argv[sys.argv.index("--") + 1:]
bpy.ops.wm.open_mainfile(filepath=args[0])
sys.argv = [args[1], "--"] + args[2:]
runpy.run_path(args[1], run_name="__main__")
