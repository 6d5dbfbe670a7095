"""(d) Bad input -> CANCELLED with an ERROR naming object and problem; nothing written."""
import math

import bpy

import rt_common as rt
import scenes

case = rt.arg("--case")
rt.setup()
out = {"case": case}
if case == "empty":
    pass
elif case == "nan":
    objs = scenes.build_diffuse_scene()
    verts, faces = rt.grid((0, 0, 1), (1, 0, 0), (0, 1, 0), 2)
    verts[4] = (math.nan, 0.0, 1.0)
    rt.mesh_object("Broken", verts, faces)
elif case == "zero_area":
    objs = scenes.build_diffuse_scene()
    # two proper triangles and two degenerate ones (collinear / repeated vertex)
    verts = [(0, 0, 0.5), (1, 0, 0.5), (0, 1, 0.5), (2, 0, 0.5), (3, 0, 0.5), (4, 0, 0.5)]
    rt.mesh_object("Degenerate", verts, [(0, 1, 2), (3, 4, 5), (2, 1, 0)])
elif case == "no_emitter":
    objs = scenes.build_diffuse_scene()
    bpy.data.objects["Light"].hide_render = True
elif case == "only_nonmesh":
    bpy.ops.mesh.primitive_plane_add()
    bpy.context.object.hide_render = True
    cu = bpy.data.curves.new("Text", "FONT")
    rt.link(bpy.data.objects.new("Text", cu))
stats_before = bpy.context.scene.radiosity.last_stats
ok, err, reports = rt.bake()
written = {o.name: (o.type == "MESH" and o.data.color_attributes.get("Radiosity") is not None)
           for o in bpy.data.objects}
vals = {}
for o in bpy.data.objects:
    c = rt.corner_colors(o) if o.type == "MESH" else None
    if c is not None:
        vals[o.name] = [float(c[:, :3].min()), float(c[:, :3].max()), bool((c[:, 3] == 1).all())]
rt.result(ok=ok, err=err, reports=reports, written=written, values=vals,
          stats_unchanged=bpy.context.scene.radiosity.last_stats == stats_before,
          stats=rt.last_stats(), **out)
