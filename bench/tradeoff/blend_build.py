"""Helpers for the scripts that build the benchmark's own scenes inside Blender (make_*.py):
Diffuse BSDF materials, gridded panels, meshes, lights, saving."""
import os
import sys

import bpy
from mathutils import Vector


def empty_scene():
    """A new empty file whose world is black; returns its scene."""
    bpy.ops.wm.read_factory_settings(use_empty=True)
    scene = bpy.context.scene
    world = bpy.data.worlds.new("Black")
    world.use_nodes = True
    world.node_tree.nodes["Background"].inputs["Strength"].default_value = 0.0
    world.color = (0, 0, 0)
    scene.world = world
    return scene


def shader_material(name, shader, inputs):
    """A material of one shader node (e.g. ShaderNodeBsdfDiffuse) with the given input values."""
    m = bpy.data.materials.new(name)
    m.use_nodes = True
    nt = m.node_tree
    for n in list(nt.nodes):
        nt.nodes.remove(n)
    out = nt.nodes.new("ShaderNodeOutputMaterial")
    d = nt.nodes.new(shader)
    for key, value in inputs.items():
        d.inputs[key].default_value = value
    nt.links.new(d.outputs[0], out.inputs["Surface"])
    return m


def material(name, rgb):
    """A matte Diffuse BSDF of colour RGB."""
    m = shader_material(name, "ShaderNodeBsdfDiffuse", {"Color": (*rgb, 1.0), "Roughness": 0.0})
    m.diffuse_color = (*rgb, 1.0)
    return m


def emission(name, rgb, strength):
    """An Emission shader (a mesh lamp: both sides of its faces emit, as Cycles has it)."""
    return shader_material(name, "ShaderNodeEmission", {"Color": (*rgb, 1.0), "Strength": strength})


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


def box(verts, faces, centre, half, cells):
    """Adds the six faces of an axis-aligned box (normals outward) as grids: half-extents HALF,
    CELLS quads along each axis."""
    for axis in range(3):
        for sign in (-1, 1):
            a1, a2 = [q for q in range(3) if q != axis]
            u, v = Vector((0, 0, 0)), Vector((0, 0, 0))
            u[a1], v[a2] = 2 * half[a1], 2 * half[a2]
            nu, nv = cells[a1], cells[a2]
            if u.cross(v)[axis] * sign < 0:
                u, v, nu, nv = v, u, nv, nu
            o = Vector(centre)
            o[axis] += sign * half[axis]
            panel(verts, faces, o - u / 2 - v / 2, u, v, nu, nv)


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


def save(out):
    """Saves the open file at OUT, without a .blend1 beside it."""
    os.makedirs(os.path.dirname(out), exist_ok=True)
    bpy.context.preferences.filepaths.save_version = 0
    bpy.ops.wm.save_as_mainfile(filepath=out, compress=True)
    print("saved", out)


def build_and_save(build, default_out):
    """Runs BUILD and saves the file at the path after "--" on Blender's command line, else at
    DEFAULT_OUT."""
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    build()
    save(os.path.abspath(argv[0] if argv else default_out))
