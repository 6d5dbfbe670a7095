"""Undo after a bake restores the previous state (where the Blender build allows undo headless)."""
import bpy

import rt_common as rt
import scenes

rt.setup()
floor, light, box = scenes.build_diffuse_scene()
out = {}
try:
    out["push"] = list(bpy.ops.ed.undo_push(message="scene built"))
except RuntimeError as exc:
    out["push_error"] = str(exc)
ok, err, _ = rt.bake()
out["baked"] = ok and floor.data.color_attributes.get("Radiosity") is not None
try:
    out["undo"] = list(bpy.ops.ed.undo())
except RuntimeError as exc:
    out["undo_error"] = str(exc)
floor = bpy.data.objects["Floor"]
out["attr_after_undo"] = floor.data.color_attributes.get("Radiosity") is not None
out["stats_after_undo"] = bpy.context.scene.radiosity.last_stats
out["bl_options"] = sorted(bpy.types.RADIOSITY_OT_bake.bl_options)
rt.result(**out)
