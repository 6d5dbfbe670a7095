"""Every kind of instance takes part, counted in last_stats: particles
(render as object), instancing vertices, a collection linked from a library .blend and
instanced by an Empty, a text object (its own surface is no instance). Also: a hidden-in-render
instancer contributes nothing, and an object with hide_render inside an instanced collection is
left out as Cycles leaves it out."""
import os

import bpy

import rt_common as rt

rt.setup()
tmp = rt.arg("--tmp")
# The library: a collection with one box, saved to a .blend of its own.
lib_path = os.path.join(tmp, "library.blend")
coll = rt.new_collection("LibProps")
v, f = rt.box((0, 0, 0), (0.3, 0.3, 0.3))
rt.mesh_object("LibBox", v, f, coll)
hidden = rt.mesh_object("LibHidden", v, f, coll)
hidden.hide_render = True
bpy.data.libraries.write(lib_path, {coll})
rt.reset()
rt.install_addon()

rt.black_world()
light = rt.emission_material("Light", (1, 1, 1), 10.0)
lv, lf = rt.grid((-0.5, -0.5, 3.0), (0, 1, 0), (1, 0, 0), 1)
rt.mesh_object("Light", lv, lf, None, light)
fv, ff = rt.grid((-3, -3, 0), (6, 0, 0), (0, 6, 0), 4)
floor = rt.mesh_object("Floor", fv, ff)
pv, pf = rt.box((0, 0, 0), (0.2, 0.2, 0.2))
src = rt.mesh_object("Pebble", pv, pf)
src.location = (0, 0, -5)
src.hide_render = True            # the source itself is not rendered; its instances are
# Particles: 6 pebbles emitted from a plate (no physics: they stay where they are born).
gv, gf = rt.grid((-1, -1, 0.5), (2, 0, 0), (0, 2, 0), 2)
plate = rt.mesh_object("Emitter", gv, gf)
ps = plate.modifiers.new("Particles", "PARTICLE_SYSTEM").particle_system.settings
ps.count, ps.frame_start, ps.frame_end = 6, 1, 1
ps.physics_type = "NO"
ps.render_type, ps.instance_object = "OBJECT", src
ps.particle_size = 1.0
plate.show_instancer_for_render = False      # the emitter plate itself is not rendered
# Instancing vertices: a 4-vertex mesh parenting a pebble.
verts = rt.mesh_object("Verts", [(1.5, 1.5, 0.4), (2.0, 1.5, 0.4), (1.5, 2.0, 0.4),
                                 (2.0, 2.0, 0.4)], [])
verts.instance_type = "VERTS"
child = rt.mesh_object("VertChild", pv, pf)
child.parent = verts
# A hidden instancer: nothing.
off = bpy.data.objects.new("OffInstancer", None)
off.instance_type, off.instance_collection = "COLLECTION", None
rt.link(off)
# A collection linked from the library, instanced twice (the second Empty hidden in render).
with bpy.data.libraries.load(lib_path, link=True) as (src_data, dst_data):
    dst_data.collections = ["LibProps"]
linked = dst_data.collections[0]
for name, loc, render in (("LibInstance", (-1.5, 1.5, 0.5), True),
                          ("LibInstanceOff", (1.5, -1.5, 0.5), False)):
    e = bpy.data.objects.new(name, None)
    e.instance_type, e.instance_collection = "COLLECTION", linked
    e.location = loc
    e.hide_render = not render
    rt.link(e)
txt = rt.link(bpy.data.objects.new("Label", bpy.data.curves.new("Label", "FONT")))
txt.location = (-2, -2, 0.01)
ok, err, reports = rt.bake()
rt.result(ok=ok, err=err, reports=reports, stats=rt.last_stats(),
          floor_written=rt.corner_colors(floor) is not None,
          library_file=bool(bpy.data.libraries))
