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
CELL = 0.2


def material(name, rgb):
    m = bpy.data.materials.new(name)
    m.use_nodes = True
    nt = m.node_tree
    for n in list(nt.nodes):
        nt.nodes.remove(n)
    out = nt.nodes.new("ShaderNodeOutputMaterial")
    d = nt.nodes.new("ShaderNodeBsdfDiffuse")
    d.inputs["Color"].default_value = (*rgb, 1.0)
    d.inputs["Roughness"].default_value = 0.0
    nt.links.new(d.outputs[0], out.inputs["Surface"])
    m.diffuse_color = (*rgb, 1.0)
    return m


def panel(verts, faces, origin, u, v, nu, nv, skip=None):
    """Adds an nu x nv grid of quads over origin + [0,1]u + [0,1]v (normal u x v); cells (i, j)
    for which skip(i, j) is true are left out (a window)."""
    origin, u, v = Vector(origin), Vector(u), Vector(v)
    base = len(verts)
    for j in range(nv + 1):
        for i in range(nu + 1):
            verts.append(origin + u * (i / nu) + v * (j / nv))
    for j in range(nv):
        for i in range(nu):
            if skip and skip(i, j):
                continue
            a = base + j * (nu + 1) + i
            faces.append((a, a + 1, a + nu + 2, a + nu + 1))


def mesh(name, verts, faces, mat, collection):
    me = bpy.data.meshes.new(name)
    me.from_pydata([tuple(p) for p in verts], [], faces)
    me.validate()
    me.update()
    obj = bpy.data.objects.new(name, me)
    me.materials.append(mat)
    collection.objects.link(obj)
    return obj


def light(name, kind, location, direction=None, **settings):
    ld = bpy.data.lights.new(name, kind)
    for k, val in settings.items():
        setattr(ld, k, val)
    obj = bpy.data.objects.new(name, ld)
    obj.location = location
    if direction is not None:   # a light shines along its local -Z
        obj.rotation_euler = (-Vector(direction)).to_track_quat("Z", "Y").to_euler()
    bpy.context.scene.collection.objects.link(obj)
    return obj


def build():
    bpy.ops.wm.read_factory_settings(use_empty=True)
    scene = bpy.context.scene
    world = bpy.data.worlds.new("Black")
    world.use_nodes = True
    world.node_tree.nodes["Background"].inputs["Strength"].default_value = 0.0
    world.color = (0, 0, 0)
    scene.world = world
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
    c, h, k = Vector((-0.2, -0.9, 0.4)), 0.4, 4
    bv, bf = [], []
    for axis in range(3):
        for sign in (-1, 1):
            a1, a2 = [q for q in range(3) if q != axis]
            u, v = Vector((0, 0, 0)), Vector((0, 0, 0))
            u[a1], v[a2] = 2 * h, 2 * h
            if u.cross(v)[axis] * sign < 0:
                u, v = v, u
            o = c.copy()
            o[axis] += sign * h
            panel(bv, bf, o - u / 2 - v / 2, u, v, k, k)
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


def main():
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    out = os.path.abspath(argv[0] if argv else os.path.join(HERE, "scenes", "lights_room.blend"))
    build()
    os.makedirs(os.path.dirname(out), exist_ok=True)
    bpy.context.preferences.filepaths.save_version = 0     # no .blend1 beside it
    bpy.ops.wm.save_as_mainfile(filepath=out, compress=True)
    print("saved", out)


main()
