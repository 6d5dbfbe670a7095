"""Scenes of the light tests (tests/blender/test_lights.py), built identically by the tests and
by make_light_references.py: a 4x4 m floor (10x10 quads, rho 0.5) with a coloured box on it
(the box of scenes.build_diffuse_scene), black world, and one Blender light (or the world)."""
import math

import bpy

import rt_common as rt

ORDER = ("Floor", "Box")

# name: (light type, light settings, location, rotation (XYZ Euler, degrees))
CASES = {
    "area_square": ("AREA", {"shape": "SQUARE", "size": 1.0, "energy": 150.0, "color": (1.0, 0.9, 0.8)},
                    (0.0, 0.0, 2.0), (0, 0, 0)),
    "area_rect": ("AREA", {"shape": "RECTANGLE", "size": 1.5, "size_y": 0.5, "energy": 150.0},
                  (-0.3, 0.2, 1.8), (20, 0, 0)),
    "area_disk": ("AREA", {"shape": "DISK", "size": 1.0, "energy": 150.0}, (0.2, 0.0, 2.0), (0, 0, 0)),
    "area_ellipse": ("AREA", {"shape": "ELLIPSE", "size": 1.2, "size_y": 0.6, "energy": 150.0},
                     (0.0, -0.2, 1.9), (0, -15, 0)),
    "point": ("POINT", {"energy": 200.0, "shadow_soft_size": 0.1, "color": (1.0, 0.8, 0.6)},
              (-0.5, -0.3, 1.5), (0, 0, 0)),
    "spot": ("SPOT", {"energy": 400.0, "shadow_soft_size": 0.05, "spot_size": math.radians(70),
                      "spot_blend": 0.3}, (-0.3, -0.5, 2.2), (15, 0, 0)),
    "sun": ("SUN", {"energy": 3.0, "angle": math.radians(3.0)}, (0.0, 0.0, 3.0), (35, 0, 30)),
    "world": ("WORLD", {"color": (0.4, 0.5, 0.7), "strength": 1.0}, None, None),
}


def add_light(name, kind, settings, location, rotation_deg):
    light = bpy.data.lights.new(name, kind)
    for k, v in settings.items():
        setattr(light, k, v)
    obj = bpy.data.objects.new(name, light)
    obj.location = location
    obj.rotation_euler = tuple(math.radians(a) for a in rotation_deg)
    return rt.link(obj)


def build(case, box_collection=True):
    """box_collection: the box in a collection (a cluster, as in scenes.build_diffuse_scene)
    or directly in the scene. The references do not depend on it (Cycles ignores collections);
    the solver's figures differ by ~0.1 % (before the oracle's near-field term the cluster links
    left the box sides 5-15 % dark)."""
    rt.black_world()
    floor_mat = rt.diffuse_material("Floor", (0.5, 0.5, 0.5))
    box_mat = rt.diffuse_material("Box", (0.7, 0.35, 0.2))
    verts, faces = rt.grid((-2, -2, 0), (4, 0, 0), (0, 4, 0), 10)
    floor = rt.mesh_object("Floor", verts, faces, None, floor_mat)
    bv, bf = rt.gridded_box([0.6, 0.3, 0.4], [0.5, 0.5, 0.4], 4)
    box = rt.mesh_object("Box", bv, bf, rt.new_collection("Props") if box_collection else None, box_mat)
    kind, settings, loc, rot = CASES[case]
    if kind == "WORLD":
        bg = bpy.context.scene.world.node_tree.nodes["Background"]
        bg.inputs["Color"].default_value = (*settings["color"], 1.0)
        bg.inputs["Strength"].default_value = settings["strength"]
    else:
        add_light(case, kind, settings, loc, rot)
    return [floor, box]


def version_tag():
    """References differ by Blender version (area and spot units changed in 4.0)."""
    return "v4" if bpy.app.version >= (4, 0, 0) else "v3"
