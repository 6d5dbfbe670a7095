"""(c) Re-baking: no duplicate attributes, unchanged scene -> kept solution, changes -> re-solve."""
import bpy
import numpy as np

import rt_common as rt
import scenes

rt.setup()
objs = scenes.build_diffuse_scene()
floor = objs[0]
# A same-named attribute of the wrong type/domain must be replaced, not duplicated.
floor.data.attributes.new("Radiosity", "FLOAT", "POINT")
out = {}
ok1, err1, _ = rt.bake()
out["first"] = rt.last_stats()
c1 = rt.corner_colors(floor).copy()
ok2, err2, _ = rt.bake()
out["second"] = rt.last_stats()
c2 = rt.corner_colors(floor)
out["same_values"] = bool(np.array_equal(c1, c2))
out["names"] = {o.name: [a.name for a in o.data.attributes if a.name == "Radiosity"] for o in objs}
out["types"] = {o.name: [(a.data_type, a.domain) for a in o.data.attributes
                         if a.name == "Radiosity"] for o in objs}
out["active"] = {o.name: o.data.color_attributes.active_color.name for o in objs}
ok3, _, _ = rt.bake(full=True)
out["full"] = rt.last_stats()
bpy.context.scene.radiosity.preset = "DRAFT"
ok4, _, _ = rt.bake()
out["preset_change"] = rt.last_stats()
objs[1].data.materials[0].node_tree.nodes["Emission"].inputs["Strength"].default_value = 5.0
ok5, _, _ = rt.bake()
out["material_change"] = rt.last_stats()
bpy.ops.radiosity.clear()
ok6, _, _ = rt.bake()
out["after_clear"] = rt.last_stats()
# last_stats is read-only from Python
try:
    bpy.context.scene.radiosity.last_stats = "x"
    out["readonly"] = False
except (AttributeError, TypeError):
    out["readonly"] = True
rt.result(ok=[ok1, ok2, ok3, ok4, ok5, ok6], err=[err1, err2], **out)
