"""Which objects take part / get written, warnings, clusters, mirrored objects."""
import bpy

import rt_common as rt
import scenes

rt.setup()
floor, light, box = scenes.build_diffuse_scene()
scene = bpy.context.scene
props = scene.radiosity
out = {}

# Mirrored floor: the result must equal the unmirrored one (the scene is symmetric in x except
# for the box, so compare against a bake without the box).
box.hide_render = True
rt.bake()
plain = rt.corner_colors(floor)[:, :3].copy()
floor.scale.x = -1.0
rt.bake()
mirrored = rt.corner_colors(floor)[:, :3].copy()
floor.scale.x = 1.0
box.hide_render = False
out["mirror_mean_ratio"] = float(mirrored.mean() / plain.mean())

def quad(name, z, coll=None, mat=None):
    v, f = rt.grid((-0.3, -0.3, z), (0.6, 0, 0), (0, 0.6, 0), 2)
    return rt.mesh_object(name, v, f, coll, mat)

hidden = quad("Hidden", 0.5); hidden.hide_set(True)
norender = quad("NoRender", 0.6); norender.hide_render = True
ex = rt.new_collection("Excluded"); quad("InExcluded", 0.7, ex)
scene.view_layers[0].layer_collection.children["Excluded"].exclude = True
nr = rt.new_collection("RenderOff"); quad("InRenderOff", 0.8, nr); nr.hide_render = True
# linked duplicate
dup = bpy.data.objects.new("FloorDup", floor.data)
rt.link(dup)
dup.location.z = -3.0
# topology-changing modifier
sub = quad("Subdivided", 1.0)
sub.modifiers.new("Subsurf", "SUBSURF")
# topology-keeping modifier (displace without texture: uniform offset along normals)
disp = quad("Displaced", 1.1)
disp.modifiers.new("Displace", "DISPLACE").strength = 0.05
# textured material used by two objects -> one warning
tex = rt.textured_material("Checker")
quad("Tex1", 1.2, None, tex)
quad("Tex2", 1.3, None, tex)
# non-mesh geometry: a text object (takes part, not written)
txt = rt.link(bpy.data.objects.new("Label", bpy.data.curves.new("Label", "FONT")))
txt.location = (1.5, 1.5, 0.01)
# object in two collections: the first collection is used
c1, c2 = rt.new_collection("First"), rt.new_collection("Second")
two = quad("TwoColls", 1.4, c1)
c2.objects.link(two)
# nested collection
inner = rt.new_collection("Inner", c1)
quad("Nested", 1.5, inner)

ok, err, reports = rt.bake()
out.update(ok=ok, err=err, reports=reports, stats=rt.last_stats())
out["written"] = {o.name: o.data.color_attributes.get("Radiosity") is not None
                  for o in bpy.data.objects if o.type == "MESH"}
# the displaced quad must have been baked from its evaluated (moved) geometry
rt.result(**out)
