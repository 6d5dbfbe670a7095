"""Converged Cycles bake to a corner colour attribute (NOTES.md settings), shared by the
reference generators of the light tests. Needs no add-on."""
import bpy

import rt_common as rt


def cycles_bake(objs, samples, name="CyclesRef", seed=1):
    scene = bpy.context.scene
    scene.render.engine = "CYCLES"
    c = scene.cycles
    c.device = "CPU"
    c.samples = samples
    c.use_adaptive_sampling = False      # otherwise it stops early
    c.use_denoising = False
    c.max_bounces = c.diffuse_bounces = 64
    c.glossy_bounces = c.transmission_bounces = c.volume_bounces = c.transparent_max_bounces = 64
    c.sample_clamp_direct = c.sample_clamp_indirect = 0.0
    c.seed = seed
    scene.render.bake.target = "VERTEX_COLORS"
    for o in bpy.data.objects:
        o.select_set(False)
    for o in objs:
        rt.fresh_bake_target(o.data, name)
        o.select_set(True)
    bpy.context.view_layer.objects.active = objs[0]
    bpy.ops.object.bake(type="COMBINED")
    return [rt.corner_colors(o, name)[:, :3].copy() for o in objs]
