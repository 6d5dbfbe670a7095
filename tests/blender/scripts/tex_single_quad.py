"""A checker on a single quad: its four corners may all fall on one colour, the polygon's
reflectance for the transport must be the checker's area mean (test_textures_world.py)."""
import bpy
import numpy as np

import rt_common as rt
import tex_world_scenes as tws

rt.setup()
from radiosity import gather  # noqa: E402  (the installed add-on)

rt.black_world()
mat = tws.checker_material()
tex = mat.node_tree.nodes["Checker Texture"]
tex.inputs["Scale"].default_value = 4.0      # 2 x 2 squares... on Generated coordinates: 4 x 4
verts, faces = rt.grid((-1, -1, 0), (2, 0, 0), (0, 2, 0), 1)
plane = rt.mesh_object("Plane", verts, faces, None, mat)
# An emitting quad whose Emission colour is the same checker, strength 5 (the EMIT bake).
emat = bpy.data.materials.new("CheckerLight")
nt, out = rt._nodes(emat)
em = nt.nodes.new("ShaderNodeEmission")
em.inputs["Strength"].default_value = 5.0
etex = nt.nodes.new("ShaderNodeTexChecker")
etex.inputs["Color1"].default_value = (1.0, 0.0, 0.0, 1.0)
etex.inputs["Color2"].default_value = (0.0, 0.0, 1.0, 1.0)
etex.inputs["Scale"].default_value = 4.0
nt.links.new(etex.outputs["Color"], em.inputs["Color"])
nt.links.new(em.outputs[0], out.inputs["Surface"])
lv, lf = rt.grid((-1, -1, 2), (0, 2, 0), (2, 0, 0), 1)
lamp = rt.mesh_object("Lamp", lv, lf, None, emat)
dg = bpy.context.evaluated_depsgraph_get()
si, _, warnings = gather.gather(bpy.context.scene, bpy.context.view_layer, dg)
o = si.objects[0]
lo = si.objects[1]
rt.result(ok=True, polygon=o.reflectance[0].tolist(), corners=o.corner_reflectance.tolist(),
          lamp_polygon=lo.emission[0].tolist(), lamp_corners=lo.corner_emission.tolist(),
          plane_emission=None if o.corner_emission is None else o.corner_emission.tolist(),
          # The pieces inside the polygons (the transport's texture; scene_data.texture_pieces).
          plane_piece_greens=sorted({round(float(g), 2) for g in o.texture_pieces[3][:, 1]}),
          plane_piece_emission=None if o.texture_pieces[4] is None else float(np.max(o.texture_pieces[4])),
          lamp_piece_emission=sorted({tuple(round(float(x), 2) for x in e) for e in lo.texture_pieces[4]}),
          piece_counts=[len(o.texture_pieces[0]), len(lo.texture_pieces[0])],
          warnings=warnings, stats=si.evaluation_stats)
