"""Report the colour attributes of every mesh of a saved file (--file for the bpy module)."""
import os

import bpy

import rt_common as rt

if rt.arg("--file") and os.path.abspath(bpy.data.filepath or "") != os.path.abspath(rt.arg("--file")):
    bpy.ops.wm.open_mainfile(filepath=rt.arg("--file"))
out = {}
for o in bpy.data.objects:
    if o.type == "MESH":
        c = rt.corner_colors(o, rt.arg("--attribute", "Radiosity"))
        out[o.name] = None if c is None else float(c[:, :3].max())
stats = bpy.context.scene.get("radiosity", {}).get("_last_stats", "") if "radiosity" in bpy.context.scene else ""
rt.result(maxima=out, stats=stats)
