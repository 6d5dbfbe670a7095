"""Two objects with the same mesh and textured material in two places (a room's floor and its
copy in the next room): their texture is evaluated once, and a move elsewhere changes neither
(test_textures_world.py)."""
import bpy
import numpy as np

import rt_common as rt
import tex_world_scenes as tws

rt.setup()
floor, light, cube = tws.build("checker")
twin = floor.copy()
twin.data = floor.data.copy()
twin.name = "Floor twin"
twin.location.x += 6.0
bpy.context.scene.collection.objects.link(twin)
bpy.context.scene.radiosity.preset = "DRAFT"
ok1, err1, _ = rt.bake()
first = rt.last_stats()
before = rt.corner_colors(twin)[:, :3].copy()
cube.location.x += 0.2
ok2, err2, _ = rt.bake()
st = rt.last_stats()
after = rt.corner_colors(twin)[:, :3]
rt.result(ok=ok1 and ok2, errs=[err1, err2], textured=first.get("textured_objects"),
          baked=first.get("textures_baked"), mode=st.get("mode"),
          texture_changed=st.get("texture_changed"), reflectance_changed=st.get("reflectance_changed"),
          twin_lit=float(before.mean()), twin_change=float(np.abs(after - before).max()))
