"""Scenes of test_scene_as_rendered.py: the scene as Blender renders it, modifiers and instances.

Built from data (no operators, no version-dependent primitives) so Blender 3.4 and bpy 5.x make
the same meshes, corner for corner; the geometry-nodes tree is built by Python in either API.
Each builder returns the names of the objects whose corners are compared with Cycles (the
written ones; emitters are not compared) and the emitter's name.
"""
import bpy

import rt_common as rt

# The default cube (2 m, at the origin): its 8 vertices and 6 faces, outward.
CUBE_VERTS, CUBE_FACES = rt.box((0.0, 0.0, 0.0), (2.0, 2.0, 2.0))


def _light(z=3.0, size=1.5, strength=10.0):
    """A square emitter of radiance `strength` at height z facing down (-z)."""
    mat = rt.emission_material("Light", (1.0, 1.0, 1.0), strength)
    h = size / 2
    v, f = rt.grid((-h, -h, z), (0, size, 0), (size, 0, 0), 1)       # u x v = -z
    return rt.mesh_object("Light", v, f, None, mat)


def _floor(z, half, n, rgb=(0.5, 0.5, 0.5)):
    mat = rt.diffuse_material("FloorMat", rgb)
    v, f = rt.grid((-half, -half, z), (2 * half, 0, 0), (0, 2 * half, 0), n)
    return rt.mesh_object("Floor", v, f, None, mat)


def build_subsurf():
    """The default cube with Subdivision Surface level 2 floating over a subdivided floor."""
    rt.black_world()
    _floor(-1.5, 4.0, 16)
    _light(z=3.0, size=1.5)
    cube = rt.mesh_object("Cube", CUBE_VERTS, CUBE_FACES, None,
                          rt.diffuse_material("CubeMat", (0.8, 0.8, 0.8)))
    m = cube.modifiers.new("Subdivision", "SUBSURF")
    m.levels = m.render_levels = 2
    return ["Floor", "Cube"], "Light"


def _box_object(name, size, location, collection, rgb):
    v, f = rt.box((0.0, 0.0, 0.0), (size, size, size))
    obj = rt.mesh_object(name, v, f, collection, rt.diffuse_material(name + "Mat", rgb))
    obj.location = location
    return obj


def _scatter_tree(source, count, offset):
    """Geometry nodes: `count` instances of object `source` along a line (Mesh Line ->
    Instance on Points), the host's own geometry dropped."""
    tree = bpy.data.node_groups.new("Scatter", "GeometryNodeTree")
    if hasattr(tree, "interface"):          # 4.0+
        tree.interface.new_socket("Geometry", in_out="INPUT", socket_type="NodeSocketGeometry")
        tree.interface.new_socket("Geometry", in_out="OUTPUT", socket_type="NodeSocketGeometry")
    else:                                   # 3.x
        tree.inputs.new("NodeSocketGeometry", "Geometry")
        tree.outputs.new("NodeSocketGeometry", "Geometry")
    tree.nodes.new("NodeGroupInput")
    out = tree.nodes.new("NodeGroupOutput")
    line = tree.nodes.new("GeometryNodeMeshLine")
    line.inputs["Count"].default_value = count
    line.inputs["Offset"].default_value = offset
    info = tree.nodes.new("GeometryNodeObjectInfo")
    info.inputs["Object"].default_value = source
    iop = tree.nodes.new("GeometryNodeInstanceOnPoints")
    tree.links.new(line.outputs[0], iop.inputs["Points"])
    tree.links.new(info.outputs["Geometry"], iop.inputs["Instance"])
    tree.links.new(iop.outputs[0], out.inputs[0])
    return tree


def build_instances():
    """Over a floor: a collection instance (an Empty instancing a collection excluded from the
    view layer), three geometry-nodes instances on points, and a box with an Array modifier.
    Only the floor and the arrayed box are written (instances have no colours of their own)."""
    rt.black_world()
    _floor(0.0, 3.0, 16)
    _light(z=2.5, size=1.5)
    props = rt.new_collection("Props")
    _box_object("Crate", 0.8, (0.0, 0.0, 0.0), props, (0.8, 0.3, 0.2))
    pebble = _box_object("Pebble", 0.4, (0.0, 0.0, 0.0), props, (0.2, 0.7, 0.3))
    bpy.context.view_layer.layer_collection.children["Props"].exclude = True
    inst = bpy.data.objects.new("CrateInstance", None)
    inst.instance_type = "COLLECTION"
    inst.instance_collection = props
    inst.location = (-1.2, -1.0, 0.6)
    # The collection holds the pebble too: the instance shows both, at their own places
    # relative to the collection's origin; move the pebble out of the crate.
    pebble.location = (0.0, 0.0, 1.0)
    rt.link(inst)
    host = rt.mesh_object("Scatter", [], [], None)
    host.location = (-0.6, 1.2, 0.35)
    gn = host.modifiers.new("Scatter", "NODES")
    gn.node_group = _scatter_tree(pebble, 3, (0.8, 0.0, 0.0))
    rail = _box_object("Rail", 0.4, (1.2, -1.6, 0.4), None, (0.6, 0.6, 0.8))
    arr = rail.modifiers.new("Array", "ARRAY")
    arr.count = 3
    arr.relative_offset_displace = (0.0, 1.8, 0.0)
    return ["Floor", "Rail"], "Light"


def build_modifiers():
    """Bevel, Mirror and Solidify over a floor (Array is in build_instances)."""
    rt.black_world()
    _floor(0.0, 3.0, 16)
    _light(z=2.5, size=1.5)
    bev = _box_object("Beveled", 0.8, (-1.2, -1.0, 0.6), None, (0.8, 0.5, 0.3))
    b = bev.modifiers.new("Bevel", "BEVEL")
    b.width, b.segments, b.limit_method = 0.08, 2, "ANGLE"
    # A box beside its object's origin, mirrored across the object's X axis: two boxes.
    v, f = rt.box((0.45, 0.0, 0.0), (0.5, 0.5, 0.5))
    mir = rt.mesh_object("Mirrored", v, f, None, rt.diffuse_material("MirMat", (0.3, 0.5, 0.8)))
    mir.location = (0.3, 1.2, 0.5)
    mir.modifiers.new("Mirror", "MIRROR")
    # A 1 m plate, thickened downwards by Solidify.
    v, f = rt.grid((-0.5, -0.5, 0.0), (1, 0, 0), (0, 1, 0), 4)
    shell = rt.mesh_object("Shell", v, f, None, rt.diffuse_material("ShellMat", (0.7, 0.7, 0.7)))
    shell.location = (1.3, -1.0, 0.9)
    sol = shell.modifiers.new("Solidify", "SOLIDIFY")
    sol.thickness, sol.offset = 0.1, -1.0
    return ["Floor", "Beveled", "Mirrored", "Shell"], "Light"


BUILDERS = {"subsurf": build_subsurf, "instances": build_instances, "modifiers": build_modifiers}
