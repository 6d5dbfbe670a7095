"""A room with an armchair built as users build one: cubes with Bevel and Subdivision Surface
modifiers (their quads are warped by the thousand), in its own collection, lit by a ceiling
lamp. Bake; move the armchair 0.5 m and turn it 0.6 rad so that it sinks into a wall, bake
again (incremental); then a full bake of the moved scene. Reports every corner's finiteness
and sign, the modes, and the incremental / full NRMSE.
"""
import bpy
import numpy as np
from mathutils import Matrix

import rt_common as rt

mod = rt.setup()
scene = bpy.context.scene
scene.radiosity.preset = rt.arg("--preset", "DRAFT")

wall = rt.diffuse_material("Wall", (0.7, 0.7, 0.7))
fabric = rt.diffuse_material("Fabric", (0.5, 0.3, 0.2))
rv, rf = rt.gridded_box((0, 0, 1.35), (2.5, 2.0, 1.35), 4)
room = rt.mesh_object("Room", rv, [tuple(reversed(f)) for f in rf], material=wall)
lv, lf = rt.grid((-0.3, -0.3, 2.65), (0, 0.6, 0), (0.6, 0, 0), 1)  # facing down
rt.mesh_object("Lamp", lv, lf, material=rt.emission_material("Lamp", (1, 1, 1), 20.0))

chair = rt.new_collection("Armchair")
parts = [("Seat", (1.0, 0.5, 0.25), (0.9, 0.8, 0.3)), ("Back", (1.0, 0.85, 0.65), (0.9, 0.15, 0.6)),
         ("ArmL", (0.5, 0.5, 0.5), (0.15, 0.8, 0.5)), ("ArmR", (1.5, 0.5, 0.5), (0.15, 0.8, 0.5))]
for name, centre, size in parts:
    v, f = rt.box(centre, size)
    o = rt.mesh_object(name, v, f, collection=chair, material=fabric)
    bev = o.modifiers.new("Bevel", "BEVEL")
    bev.width = 0.04
    bev.segments = 3
    sub = o.modifiers.new("Subdivision", "SUBSURF")
    sub.levels = 1
    sub.render_levels = 1
bpy.context.view_layer.update()


def sane(c):
    x = np.concatenate(list(c.values()))
    return bool(np.all(np.isfinite(x)) and np.all(x >= 0)), int(x.shape[0])


ok, out = [], {}
ok.append(rt.bake()[0])
out["first"] = rt.last_stats()
out["first_sane"], out["corners"] = sane(rt.mesh_colours(scene))

# 0.5 m toward the +x wall and a turn of 0.6 rad about the vertical through the seat: the
# right arm ends inside the wall.
turn = (Matrix.Translation((1.0 + 0.5, 0.5, 0)) @ Matrix.Rotation(0.6, 4, "Z")
        @ Matrix.Translation((-1.0, -0.5, 0)))
for o in chair.objects:
    o.matrix_world = turn @ o.matrix_world
bpy.context.view_layer.update()
ok.append(rt.bake()[0])
out["move"] = rt.last_stats()
inc = rt.mesh_colours(scene)
out["move_sane"], _ = sane(inc)
ok.append(rt.bake(full=True)[0])
out["move_full"] = rt.last_stats()
full = rt.mesh_colours(scene)
out["full_sane"], _ = sane(full)
out["nrmse"] = rt.colours_nrmse(inc, full)
out["ok"] = ok
rt.result(**out)
