"""Save scenes.build_diffuse_scene() to --out (no add-on involved)."""
import bpy

import rt_common as rt
import scenes

rt.reset()
scenes.build_diffuse_scene()
bpy.ops.wm.save_as_mainfile(filepath=rt.arg("--out"))
rt.result(saved=rt.arg("--out"))
