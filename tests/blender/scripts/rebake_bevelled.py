"""A cushion as users make one (Blender's cube with its UV map, Bevel, then Subdivision
Surface) on a floor under a lamp, baked twice (the second a full bake again, with the first
bake's colours in the mesh). Bevel takes each new face's original index from a neighbour it
chooses by the corner data, colours included, so a corner map read with our own colours in
the mesh would move corners between bakes. Reports both bakes' corners of the cushion.
"""
import bpy
import numpy as np

import rt_common as rt

mod = rt.setup()
scene = bpy.context.scene
scene.radiosity.preset = rt.arg("--preset", "DRAFT")

fv, ff = rt.grid((-2, -2, 0), (4, 0, 0), (0, 4, 0), 4)
rt.mesh_object("Floor", fv, ff, material=rt.diffuse_material("Floor", (0.6, 0.6, 0.6)))
lv, lf = rt.grid((-0.4, -0.4, 2.5), (0, 0.8, 0), (0.8, 0, 0), 1)  # facing down
rt.mesh_object("Lamp", lv, lf, material=rt.emission_material("Lamp", (1, 1, 1), 10.0))
bpy.ops.mesh.primitive_cube_add(size=1.0, location=(0.0, 0.0, 0.3))
cushion = bpy.context.active_object
cushion.name = "Cushion"
cushion.scale = (0.8, 0.58, 0.14)
bpy.ops.object.transform_apply(scale=True)
cushion.data.materials.append(rt.diffuse_material("Fabric", (0.5, 0.3, 0.2)))
bev = cushion.modifiers.new("Bevel", "BEVEL")
bev.width, bev.segments, bev.limit_method = 0.04, 1, "ANGLE"
sub = cushion.modifiers.new("Subdivision", "SUBSURF")
sub.levels = sub.render_levels = 1
bpy.context.view_layer.update()

ok = [rt.bake()[0]]
first = rt.corner_colors(cushion)
ok.append(rt.bake(full=True)[0])
second = rt.corner_colors(cushion)
rt.result(ok=ok, uv_maps=len(cushion.data.uv_layers), corners=int(first.shape[0]),
          first=first.tolist(), second=second.tolist(), fake=rt.native_is_fake())
