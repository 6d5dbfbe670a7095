"""Interactive Blender (Xvfb): the Bake button on a textured floor under a Sky Texture world
(textures.py, world.py evaluate them with Cycles in temporary scenes during the bake), then
undo and redo: the temporary data never shows, undo takes the colours away, redo brings them
back, and bpy.data holds what it held before (test_textures_world.py)."""
import bpy

import rt_common as rt
import tex_world_scenes as tws
import ui_steps as ui
import ui_undo as steps
from ui_steps import out

S = {}


def census():
    return {k: sorted(x.name for x in getattr(bpy.data, k))
            for k in ("scenes", "objects", "meshes", "materials", "worlds", "cameras")}


def setup():
    ui.install_and_open(None)
    for o in list(bpy.data.objects):
        bpy.data.objects.remove(o, do_unlink=True)
    S["objs"] = [o.name for o in tws.build("checker")[::2]]       # Floor, Cube: no Light
    bpy.data.objects.remove(bpy.data.objects["Light"], do_unlink=True)
    tws.sky_world()
    bpy.context.scene.radiosity.preset = "DRAFT"
    steps.push("scene made")
    S["before"] = census()


def after_bake():
    st = rt.last_stats()
    out["bake"] = {"textured_objects": st.get("textured_objects"), "world_sun": st.get("world_sun"),
                   "census_same": census() == S["before"],
                   "colours": sorted(ui.colours(S["objs"]).keys())}


def after_undo():
    out["undo"] = {"colours": sorted(ui.colours(S["objs"]).keys()),
                   "census_same": census() == S["before"]}


def after_redo():
    out["redo"] = {"colours": sorted(ui.colours(S["objs"]).keys()),
                   "census_same": census() == S["before"]}


ui.run(setup, *steps.pressed_bake(), after_bake, steps.undo, ui.pause(1.0), after_undo,
       steps.redo, ui.pause(1.0), after_redo, ui.finish)
