"""Open each example file with its UI and report how its 3D viewports look at the scene.

Run with the example paths after `--`; prints RESULT {file: {...}}."""
import os

import bpy

import rt_common as rt

out = {}
for path in rt.script_args():
    if not path.endswith(".blend"):
        continue
    bpy.ops.wm.open_mainfile(filepath=path, load_ui=True)
    views = [space.region_3d.view_perspective
             for screen in bpy.data.screens for area in screen.areas
             for space in area.spaces if space.type == "VIEW_3D"]
    camera = bpy.context.scene.camera
    out[os.path.basename(path)] = {"views": views,
                                   "camera": camera.name if camera is not None else None}
rt.result(files=out)
