"""Scenes of tests/blender/test_textures_world.py: a floor with an
image texture or a procedural (checker) texture under a white cube lit by an emitting quad, and
a floor and a cube lit only by a Sky Texture world. Objects in ORDER; no add-on needed."""
import bpy
import numpy as np

import rt_common as rt

ORDER = ("Floor", "Light", "Cube")       # the sky scene has no Light
SUN_ELEVATION, SUN_ROTATION = np.radians(35.0), np.radians(40.0)


def _cube(name, material):
    """A white 1 m cube standing on the floor beside the centre, 4 x 4 quads per side."""
    bv, bf = rt.gridded_box([0.5, 0.3, 0.5], [0.5, 0.5, 0.5], 4)
    return rt.mesh_object(name, bv, bf, None, material)


def _floor(material, n=12):
    verts, faces = rt.grid((-2, -2, 0), (4, 0, 0), (0, 4, 0), n)
    floor = rt.mesh_object("Floor", verts, faces, None, material)
    me = floor.data
    uv = me.uv_layers.new(name="UVMap")
    co = np.array([tuple(me.vertices[l.vertex_index].co) for l in me.loops])
    uv.data.foreach_set("uv", ((co[:, :2] + 2.0) / 4.0).astype(np.float32).ravel())
    return floor


def _light():
    lv, lf = rt.grid((-0.5, -0.5, 2.0), (0, 1, 0), (1, 0, 0), 1)     # normal -z
    return rt.mesh_object("Light", lv, lf, None, rt.emission_material("Light", (1, 1, 1), 10.0))


def checker_material():
    mat = bpy.data.materials.new("Checker")
    nt, out = rt._nodes(mat)
    d = nt.nodes.new("ShaderNodeBsdfDiffuse")
    tex = nt.nodes.new("ShaderNodeTexChecker")
    tex.inputs["Color1"].default_value = (0.8, 0.06, 0.05, 1.0)
    tex.inputs["Color2"].default_value = (0.8, 0.8, 0.8, 1.0)
    tex.inputs["Scale"].default_value = 3.3      # squares of 0.3 m on Generated coordinates
    nt.links.new(tex.outputs["Color"], d.inputs["Color"])
    nt.links.new(d.outputs[0], out.inputs["Surface"])
    mat.diffuse_color = (0.3, 0.4, 0.5, 1.0)
    return mat


def _pattern(size=64):
    """A byte (sRGB) image: green/blue stripes over a red-to-yellow gradient."""
    y, x = np.mgrid[0:size, 0:size] / (size - 1.0)
    r = 0.9 * np.ones_like(x)
    g = 0.1 + 0.8 * x
    b = np.where((np.floor(y * 6) % 2) == 0, 0.1, 0.7)
    g = np.where((np.floor(y * 6) % 2) == 0, g, 0.3)
    return np.stack([r, g, b, np.ones_like(x)], axis=-1).astype(np.float32)


def image_material():
    img = bpy.data.images.new("Pattern", 64, 64, alpha=False)
    img.colorspace_settings.name = "sRGB"
    img.pixels.foreach_set(_pattern(64).ravel())
    img.pack()
    mat = bpy.data.materials.new("Image")
    nt, out = rt._nodes(mat)
    d = nt.nodes.new("ShaderNodeBsdfDiffuse")
    tex = nt.nodes.new("ShaderNodeTexImage")
    tex.image = img
    tex.interpolation = "Linear"
    uvn = nt.nodes.new("ShaderNodeUVMap")
    uvn.uv_map = "UVMap"
    nt.links.new(uvn.outputs["UV"], tex.inputs["Vector"])
    nt.links.new(tex.outputs["Color"], d.inputs["Color"])
    nt.links.new(d.outputs[0], out.inputs["Surface"])
    return mat


def build_textured(kind):
    """kind: 'checker' | 'image'."""
    rt.black_world()
    mat = checker_material() if kind == "checker" else image_material()
    floor = _floor(mat)
    light = _light()
    cube = _cube("Cube", rt.diffuse_material("White", (0.8, 0.8, 0.8)))
    return [floor, light, cube]


def sky_world():
    scene = bpy.context.scene
    world = rt.node_world("Sky")
    nt = world.node_tree
    bg = nt.nodes.get("Background")
    sky = nt.nodes.new("ShaderNodeTexSky")
    if bpy.app.version < (5, 0, 0):
        sky.sky_type = "NISHITA"
    sky.sun_disc = True
    sky.sun_elevation = float(SUN_ELEVATION)
    sky.sun_rotation = float(SUN_ROTATION)
    nt.links.new(sky.outputs["Color"], bg.inputs["Color"])
    bg.inputs["Strength"].default_value = 0.1
    scene.world = world
    return world


def build_sky():
    sky_world()
    floor = _floor(rt.diffuse_material("Grey", (0.5, 0.5, 0.5)))
    cube = _cube("Cube", rt.diffuse_material("White", (0.8, 0.8, 0.8)))
    return [floor, cube]


def build(kind):
    return build_sky() if kind == "sky" else build_textured(kind)
