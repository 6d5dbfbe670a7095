"""Build the lamp box: a closed Cornell-type box lit by a mesh lamp hanging 1 cm under its
gridded ceiling, the scene where a bake read every surface 1-1.5 % brighter than Cycles.

    blender -b --factory-startup --python bench/tradeoff/make_lamp_box.py -- [OUT.blend]

(default bench/tradeoff/scenes/lamp_box.blend; made with Debian's Blender 3.4 so newer ones open
it). A 2 x 2 x 2 m box, inward normals, 0.1 m quads: white floor, ceiling, back and front walls,
a red left and a green right wall. A 0.5 x 0.5 m emitting quad (Emission, both sides light, as
in Cycles) 1 cm under the ceiling, its outline across the ceiling's cells. Two blocks standing
on the floor, each in a collection of its own (the floor under them and their bottoms are
covered corners). Black world, Diffuse BSDF materials, no Blender lights.
"""
import math
import os
import sys

import bpy

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
from blend_build import build_and_save, box, emission, empty_scene, material, mesh, panel  # noqa: E402

CELL = 0.1


def block(name, centre, half, turn, rgb):
    coll = bpy.data.collections.new(name + "Object")
    bpy.context.scene.collection.children.link(coll)
    verts, faces = [], []
    box(verts, faces, (0, 0, 0), half, [max(1, round(2 * h / CELL)) for h in half])
    obj = mesh(name, verts, faces, material(name, rgb), coll)
    obj.location = centre
    obj.rotation_euler = (0, 0, turn)


def build():
    scene = empty_scene()
    root = scene.collection
    S, n = 2.0, round(2.0 / CELL)
    x0 = y0 = -S / 2
    white, red, green = (0.73, 0.73, 0.73), (0.63, 0.065, 0.05), (0.14, 0.45, 0.09)
    v, f = [], []
    panel(v, f, (x0, y0, 0), (S, 0, 0), (0, S, 0), n, n)            # floor, normal +z
    panel(v, f, (x0, y0, S), (0, S, 0), (S, 0, 0), n, n)            # ceiling, normal -z
    panel(v, f, (x0, -y0, 0), (S, 0, 0), (0, 0, S), n, n)           # back (+y), normal -y
    panel(v, f, (x0, y0, 0), (0, 0, S), (S, 0, 0), n, n)            # front (-y), normal +y
    mesh("Room", v, f, material("White", white), root)
    v, f = [], []
    panel(v, f, (x0, y0, 0), (0, S, 0), (0, 0, S), n, n)            # -x, normal +x
    mesh("LeftWall", v, f, material("Red", red), root)
    v, f = [], []
    panel(v, f, (-x0, y0, 0), (0, 0, S), (0, S, 0), n, n)           # +x, normal -x
    mesh("RightWall", v, f, material("Green", green), root)
    z, a = S - 0.01, 0.25
    v, f = [], []
    panel(v, f, (-a, -a, z), (0, 2 * a, 0), (2 * a, 0, 0), 1, 1)    # normal -z
    mesh("Lamp", v, f, emission("Lamp", (1.0, 0.95, 0.85), 12.0), root)
    block("ShortBlock", (0.4, -0.35, 0.3), (0.3, 0.3, 0.3), math.radians(-17), white)
    block("TallBlock", (-0.4, 0.35, 0.6), (0.3, 0.3, 0.6), math.radians(18), white)


build_and_save(build, os.path.join(HERE, "scenes", "lamp_box.blend"))
