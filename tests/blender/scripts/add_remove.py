"""Objects added and deleted between bakes (the goal: "added -> linked in; deleted -> removed"):
bake the diffuse scene; add a cube in a new collection and bake (incremental), then bake in
full and compare; move the added cube (incremental, relative to where it was added); scale it
and put it in another collection (replaced: removed and added again); delete the Box
(incremental) and compare again; hide the cube from render (it leaves the bake like a deleted
object).
"""
import bpy
import numpy as np

import rt_common as rt
import scenes

mod = rt.setup()
scenes.build_diffuse_scene()
scene = bpy.context.scene
scene.radiosity.preset = rt.arg("--preset", "MEDIUM")


def worst(a, b):
    per = {k: float(np.sqrt(np.mean((a[k] - b[k]) ** 2)) / max(np.sqrt(np.mean(b[k] ** 2)), 1e-12))
           for k in set(a) & set(b)}
    k = max(per, key=per.get)
    return [k, per[k]]


def step(name):
    """Incremental bake, then a full bake of the same scene; their stats and NRMSE."""
    ok.append(rt.bake()[0])
    out[name] = rt.last_stats()
    inc = rt.mesh_colours(scene)
    ok.append(rt.bake(full=True)[0])
    out[name + "_full"] = rt.last_stats()
    full = rt.mesh_colours(scene)
    out[name + "_nrmse"] = rt.colours_nrmse(inc, full)
    out[name + "_worst"] = worst(inc, full)
    return inc


ok, out = [], {}
ok.append(rt.bake()[0])
out["first"] = rt.last_stats()

# 1) A cube added in a new collection, placed by its matrix (local vertices about the origin).
v, f = rt.box((0, 0, 0), (0.6, 0.6, 0.7))
cube = rt.mesh_object("Cube", v, f, rt.new_collection("Added"),
                      rt.diffuse_material("CubeMat", (0.3, 0.6, 0.3)))
cube.location = (-1.0, -0.8, 0.35)
bpy.context.view_layer.update()
inc = step("add")
out["cube_lit"] = bool("Cube" in inc and float(inc["Cube"].sum()) > 0)

# 2) The added cube moved: a rigid move relative to the placement it was added with.
cube.location = (-0.6, -1.2, 0.35)
bpy.context.view_layer.update()
step("move")

# 2b) The cube scaled (not a rigid move) and moved to another collection: replaced (removed and
# added again under its name).
cube.scale = (1.3, 1.0, 0.8)
coll = bpy.data.collections["Added"]
coll.objects.unlink(cube)
rt.new_collection("Moved").objects.link(cube)
bpy.context.view_layer.update()
step("replace")

# 3) The Box deleted (its collection "Props" is left empty).
bpy.data.objects.remove(bpy.data.objects["Box"], do_unlink=True)
bpy.context.view_layer.update()
step("remove")
out["box_gone"] = "Box" not in bpy.data.objects

# 4) The cube hidden from render: it leaves the bake like a deleted object.
cube.hide_render = True
bpy.context.view_layer.update()
step("hide")

print("ADDREMOVE", {k: v for k, v in out.items() if "nrmse" in k or "worst" in k},
      {k: out[k]["seconds"] for k in out if isinstance(out[k], dict) and "seconds" in out[k]})
rt.result(ok=ok, **out)
