"""Build the lights room, the fifth scene of the trade-off (presets are judged on the
four example scenes and a scene with point, spot, area and sun lights), and save it.

    blender -b --factory-startup --python bench/tradeoff/make_lights_room.py -- [OUT.blend]

(default bench/tradeoff/scenes/lights_room.blend; run it with Debian's Blender 3.4, the oldest
we support, so newer ones open the file; 3.4's area and spot units: see
addon/radiosity/core/lights.py). A 4 x 4 x 2.8 m room (inward normals, 0.2 m quads), a window
1.2 x 1.0 m in the +x wall, a 0.8 m cube on the floor in a collection of its own (floor vertices
under it and its bottom face are covered corners), black world, and four Blender lights: a
point light, a spot aimed at the cube, a square area light under the ceiling, and a sun whose
light comes in through the window onto the floor and the cube. Diffuse BSDF materials only.
"""
import math
import os
import sys

import bpy
from mathutils import Vector

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
from blend_build import build_and_save, box, empty_scene, light, material, mesh, panel  # noqa: E402
CELL = 0.2


def build():
    scene = empty_scene()
    root = scene.collection
    W, H, n, nh = 4.0, 2.8, round(4.0 / CELL), round(2.8 / CELL)
    x0 = y0 = -W / 2
    # Floor (normal +z) and ceiling (normal -z).
    fv, ff = [], []
    panel(fv, ff, (x0, y0, 0), (W, 0, 0), (0, W, 0), n, n)
    mesh("Floor", fv, ff, material("Floor", (0.55, 0.5, 0.45)), root)
    cv, cf = [], []
    panel(cv, cf, (x0, y0, H), (0, W, 0), (W, 0, 0), n, n)
    mesh("Ceiling", cv, cf, material("Ceiling", (0.8, 0.8, 0.8)), root)
    # Walls, normals (u x v) inward. The +x wall has the window: y in [-0.6, 0.6], z in [0.8, 1.8].
    wv, wf = [], []
    panel(wv, wf, (x0, y0, 0), (0, W, 0), (0, 0, H), n, nh)                         # -x, normal +x
    window = lambda i, j: 4 <= i < 9 and 7 <= j < 13                              # noqa: E731
    panel(wv, wf, (-x0, y0, 0), (0, 0, H), (0, W, 0), nh, n, skip=window)          # +x, normal -x
    panel(wv, wf, (x0, y0, 0), (0, 0, H), (W, 0, 0), nh, n)                         # -y, normal +y
    panel(wv, wf, (x0, -y0, 0), (W, 0, 0), (0, 0, H), n, nh)                        # +y, normal -y
    mesh("Walls", wv, wf, material("Walls", (0.7, 0.68, 0.62)), root)
    # The cube in its own collection (a dynamic object).
    coll = bpy.data.collections.new("CubeObject")
    root.children.link(coll)
    bv, bf = [], []
    box(bv, bf, (-0.2, -0.9, 0.4), (0.4, 0.4, 0.4), (4, 4, 4))
    mesh("Cube", bv, bf, material("Cube", (0.25, 0.45, 0.7)), coll)
    # Lights (Blender 3.4 units).
    light("Point", "POINT", (1.2, 1.2, 2.0), energy=120.0, shadow_soft_size=0.1,
          color=(1.0, 0.85, 0.7))
    light("Spot", "SPOT", (-1.4, 1.3, 2.5), direction=(1.2, -2.2, -2.1), energy=300.0,
          shadow_soft_size=0.05, spot_size=math.radians(50), spot_blend=0.25,
          color=(0.8, 0.9, 1.0))
    light("Area", "AREA", (0.9, -1.1, 2.7), direction=(0, 0, -1), energy=100.0, shape="SQUARE",
          size=0.8)
    el, az = math.radians(35), math.radians(15)
    light("Sun", "SUN", (3.5, 0, 3.5),
          direction=(-math.cos(el) * math.cos(az), -math.cos(el) * math.sin(az), -math.sin(el)),
          energy=6.0, angle=math.radians(2.0), color=(1.0, 0.95, 0.85))
    scene["radiosity_input_objects"] = 1


build_and_save(build, os.path.join(HERE, "scenes", "lights_room.blend"))
