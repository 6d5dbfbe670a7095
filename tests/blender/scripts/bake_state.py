"""Headless (both flavours): which bake the meshes show and the panel's words: tokens in the meshes,
out of date after a move with Live off, fresh again after a bake, a cached rewrite naming the bake
it repeats, records saved with the file, the tooltips."""
import json
import os
import sys

import bpy

import rt_common as rt
import scenes

mod = rt.setup()
scenes.build_diffuse_scene()
scene = bpy.context.scene
scene.radiosity.preset = "DRAFT"
out = {}


def state():
    return mod.handlers.settle(bpy.context.scene)


def describe():
    return mod.core.stats.describe(rt.last_stats())


def move_box(dx):
    box = bpy.data.objects["Box"]
    box.location.x += dx
    bpy.context.view_layer.update()     # depsgraph_update_post, as a drag's redraw sends


ok, err, _ = rt.bake()
out["ok"] = ok
tokens = {o.name: o.data.get(mod.baked_state.TOKEN_KEY) for o in bpy.data.objects
          if o.type == "MESH"}
out["tokens_one_per_bake"] = len(set(tokens.values())) == 1 and None not in tokens.values()
out["fresh_after_bake"] = state().stale
out["first"] = describe()
move_box(0.5)
out["stale_after_move"] = state().stale
move_box(-0.5)
out["stale_after_move_back"] = state().stale
move_box(0.5)
rt.bake()
out["second"] = describe()
out["stale_after_second"] = state().stale
out["new_token"] = bpy.data.objects["Floor"].data.get(mod.baked_state.TOKEN_KEY) != tokens["Floor"]
rt.bake()
out["cached"] = rt.last_stats().get("cached")
out["third"] = describe()
scene.radiosity.live = True
move_box(-0.3)
out["runs"] = mod.pump(timeout=300)
out["live"] = describe()
out["stale_after_live"] = state().stale
scene.radiosity.live = False
scene.radiosity.preset = "MEDIUM"
rt.bake()                                      # settings changed: solved in full, says why
out["settings"] = describe()
# Tooltips: description() with the operator's real properties, as the buttons pass them.
props = bpy.context.window_manager.operator_properties_last("radiosity.bake")
props.full = False
out["tip_bake"] = mod.operators.RADIOSITY_OT_bake.description(bpy.context, props)
props.full = True
out["tip_full"] = mod.operators.RADIOSITY_OT_bake.description(bpy.context, props)
clear = bpy.ops.radiosity.clear.get_rna_type()
out["clear"] = [clear.name, clear.description]
# The file keeps the records: after opening it the bake shown is known, and a move with Live
# off makes it out of date.
path = os.path.join(rt.arg("--tmp"), "state.blend")
bpy.ops.wm.save_as_mainfile(filepath=path)
bpy.ops.wm.open_mainfile(filepath=path)
mod = sys.modules["radiosity"]
out["loaded_known"] = state().shown.record is not None
out["loaded_stale"] = state().stale
out["loaded_kept"] = mod.core.session.kept(mod.bake.scene_key(bpy.context.scene)) is not None
move_box(0.4)
out["loaded_stale_after_move"] = state().stale
rt.bake()
out["after_load_bake"] = describe()
rt.result(**out)
