"""Only what is written is gathered: a floor, an emitting panel and a written box, with a
collection instanced twice (its collection excluded) and an area light. The bake's
gather_corners count the written meshes' corners alone; the written colours are those of the
same bake made with every object gathered (the add-on's hand-over patched to drop the flag),
bit for bit."""
import sys

import bpy

import rt_common as rt

rt.setup()
scene = bpy.context.scene
scene.radiosity.preset = rt.arg("--preset", "DRAFT")
rt.black_world()
lv, lf = rt.grid((-0.5, -0.5, 2.5), (0, 1, 0), (1, 0, 0), 1)
rt.mesh_object("Light", lv, lf, None, rt.emission_material("Lamp", (1, 1, 1), 10.0))
fv, ff = rt.grid((-3, -3, 0), (6, 0, 0), (0, 6, 0), 8)
rt.mesh_object("Floor", fv, ff, None, rt.diffuse_material("Grey", (0.6, 0.6, 0.6)))
bv, bf = rt.gridded_box((1.2, 1.0, 0.3), (0.3, 0.3, 0.3), 2)
rt.mesh_object("Box", bv, bf, None, rt.diffuse_material("Red", (0.8, 0.2, 0.1)))
props = rt.new_collection("Props")
cv, cf = rt.gridded_box((0, 0, 0.25), (0.25, 0.25, 0.25), 2)
rt.mesh_object("Crate", cv, cf, props, rt.diffuse_material("Blue", (0.1, 0.3, 0.8)))
bpy.context.view_layer.layer_collection.children["Props"].exclude = True
for name, loc in (("CrateA", (-1.0, -0.8, 0.0)), ("CrateB", (0.2, -1.4, 0.0))):
    e = bpy.data.objects.new(name, None)
    e.instance_type, e.instance_collection = "COLLECTION", props
    e.location = loc
    rt.link(e)
area = bpy.data.lights.new("Area", "AREA")
area.energy, area.size = 50.0, 0.5
lamp = rt.link(bpy.data.objects.new("Area", area))
lamp.location = (1.5, -1.5, 2.0)

written = ("Floor", "Light", "Box")
ok, err, reports = rt.bake(full=True)
stats = rt.last_stats()
colours = {n: rt.corner_colors(bpy.data.objects[n]) for n in written}
corners = {n: len(bpy.data.objects[n].data.loops) for n in written}

# The same bake with every object gathered, as before the flag: the hand-over passes none.
sd = sys.modules[rt.ADDON + ".core.scene_data"]
hand_over = sd.add_native_object


def gather_all(target, obj, cluster_id):
    was = obj.output
    obj.output = True
    try:
        return hand_over(target, obj, cluster_id)
    finally:
        obj.output = was


sd.add_native_object = gather_all
ok_all, err_all, _ = rt.bake(full=True)
sd.add_native_object = hand_over
stats_all = rt.last_stats()
same = {n: bool((rt.corner_colors(bpy.data.objects[n]) == colours[n]).all()) for n in written}
rt.result(ok=ok and ok_all, err=err or err_all, reports=reports, stats=stats, stats_all=stats_all,
          corners=corners, same=same, lit={n: float(colours[n][:, :3].sum()) for n in written},
          fake=rt.native_is_fake())
