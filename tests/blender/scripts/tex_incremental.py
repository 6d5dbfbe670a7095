"""A texture change is an incremental bake that equals a full one (test_textures_world.py)."""
import bpy
import numpy as np

import rt_common as rt
import tex_world_scenes as tws

rt.setup()
objs = tws.build("checker")
bpy.context.scene.radiosity.preset = "MEDIUM"
out = {}
ok1, err1, _ = rt.bake()
first = np.concatenate([rt.corner_colors(o)[:, :3] for o in objs])
tex = bpy.data.materials["Checker"].node_tree.nodes["Checker Texture"]
tex.inputs["Color1"].default_value = (0.05, 0.7, 0.1, 1.0)      # red squares turn green
ok2, err2, _ = rt.bake()
st = rt.last_stats()
inc = np.concatenate([rt.corner_colors(o)[:, :3] for o in objs])
ok3, err3, _ = rt.bake(full=True)
full = np.concatenate([rt.corner_colors(o)[:, :3] for o in objs])
n0 = len(objs[0].data.loops)
out.update(ok=ok1 and ok2 and ok3, errs=[err1, err2, err3], mode=st["mode"],
           texture_changed=st.get("texture_changed"), reflectance_changed=st.get("reflectance_changed"),
           changed_floor=float(np.abs(inc[:n0] - first[:n0]).max()),
           inc_vs_full=float(np.sqrt(np.mean((inc - full) ** 2)) / np.sqrt(np.mean(full ** 2))),
           cube_green_over_red=float(inc[n0 + 4:, 1].mean() / inc[n0 + 4:, 0].mean()))
# A move of the cube (the floor's texture reads its own Generated coordinates): the floor is
# not baked again, and a world rendered once is not rendered again.
objs[2].location.x += 0.2
rt.bake()
out["move_textures_baked"] = rt.last_stats().get("textures_baked")
import tex_world_scenes as tws2  # noqa: E402
tws2.sky_world()
rt.bake()
first_world = rt.last_stats()
objs[2].location.x -= 0.2
rt.bake()
again = rt.last_stats()
out["world_cached"] = [first_world.get("world_cached", False), again.get("world_cached", False)]
rt.result(**out)
