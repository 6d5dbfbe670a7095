"""Helpers for the scripts that run inside real Blender (binary or the PyPI bpy module).

Every script: parse its own args after "--", reset to an empty factory scene, install + enable the
add-on zip, build its scene, act, and print one line ``RESULT {json}`` that the pytest side reads.
"""
import json
import os
import sys

import bpy
import numpy as np

from box_grid import grid, gridded_box  # noqa: F401  (re-exported for the scripts)

ADDON = "radiosity"


def script_args():
    argv = sys.argv
    return argv[argv.index("--") + 1:] if "--" in argv else []


def arg(name, default=None):
    a = script_args()
    if name in a:
        return a[a.index(name) + 1]
    return default


def cases(every):
    """The cases --cases names (comma-separated), else `every` one."""
    only = arg("--cases")
    return only.split(",") if only else every


def reset():
    bpy.ops.wm.read_factory_settings(use_empty=True)


def install_addon(zip_path=None):
    """addon_install + addon_enable from the zip (the contract's install path)."""
    zip_path = zip_path or arg("--zip")
    bpy.ops.preferences.addon_install(filepath=os.path.abspath(zip_path), overwrite=True)
    bpy.ops.preferences.addon_enable(module=ADDON)
    import radiosity  # noqa: F401  (the installed package)
    return sys.modules[ADDON]


def setup():
    reset()
    mod = install_addon()
    return mod


def result(**data):
    print("RESULT " + json.dumps(data), flush=True)


def link(obj, collection=None):
    (collection or bpy.context.scene.collection).objects.link(obj)
    return obj


def new_collection(name, parent=None):
    coll = bpy.data.collections.new(name)
    (parent or bpy.context.scene.collection).children.link(coll)
    return coll


def mesh_object(name, verts, faces, collection=None, material=None):
    me = bpy.data.meshes.new(name)
    me.from_pydata([tuple(map(float, v)) for v in verts], [], [tuple(map(int, f)) for f in faces])
    me.update()
    obj = bpy.data.objects.new(name, me)
    if material is not None:
        me.materials.append(material)
    return link(obj, collection)


def box(center, size, inward=False):
    """Axis-aligned box as one mesh (6 quads), outward or inward normals."""
    c = np.asarray(center, float)
    h = np.asarray(size, float) / 2
    verts = [c + h * np.array(s) for s in
             [(-1, -1, -1), (1, -1, -1), (1, 1, -1), (-1, 1, -1),
              (-1, -1, 1), (1, -1, 1), (1, 1, 1), (-1, 1, 1)]]
    faces = [(0, 3, 2, 1), (4, 5, 6, 7), (0, 1, 5, 4), (1, 2, 6, 5), (2, 3, 7, 6), (3, 0, 4, 7)]
    if inward:
        faces = [tuple(reversed(f)) for f in faces]
    return verts, faces


def _nodes(mat):
    if bpy.app.version < (5, 0, 0):
        mat.use_nodes = True
    nt = mat.node_tree
    for n in list(nt.nodes):
        nt.nodes.remove(n)
    out = nt.nodes.new("ShaderNodeOutputMaterial")
    return nt, out


def diffuse_material(name, rgb):
    mat = bpy.data.materials.new(name)
    nt, out = _nodes(mat)
    d = nt.nodes.new("ShaderNodeBsdfDiffuse")
    d.inputs["Color"].default_value = (*rgb, 1.0)
    nt.links.new(d.outputs[0], out.inputs["Surface"])
    return mat


def emission_material(name, rgb, strength):
    mat = bpy.data.materials.new(name)
    nt, out = _nodes(mat)
    e = nt.nodes.new("ShaderNodeEmission")
    e.inputs["Color"].default_value = (*rgb, 1.0)
    e.inputs["Strength"].default_value = strength
    nt.links.new(e.outputs[0], out.inputs["Surface"])
    return mat


def principled_material(name, base, emission=(0, 0, 0), strength=0.0):
    mat = bpy.data.materials.new(name)
    nt, out = _nodes(mat)
    p = nt.nodes.new("ShaderNodeBsdfPrincipled")
    p.inputs["Base Color"].default_value = (*base, 1.0)
    e_sock = p.inputs.get("Emission Color") or p.inputs.get("Emission")   # 4.x / 3.x names
    e_sock.default_value = (*emission, 1.0)
    p.inputs["Emission Strength"].default_value = strength
    nt.links.new(p.outputs[0], out.inputs["Surface"])
    return mat


def add_diffuse_emission_material(name, rgb, emission, strength):
    """Add Shader(Diffuse, Emission): reflectance rgb and radiance emission*strength."""
    mat = bpy.data.materials.new(name)
    nt, out = _nodes(mat)
    d = nt.nodes.new("ShaderNodeBsdfDiffuse")
    d.inputs["Color"].default_value = (*rgb, 1.0)
    e = nt.nodes.new("ShaderNodeEmission")
    e.inputs["Color"].default_value = (*emission, 1.0)
    e.inputs["Strength"].default_value = strength
    add = nt.nodes.new("ShaderNodeAddShader")
    nt.links.new(d.outputs[0], add.inputs[0])
    nt.links.new(e.outputs[0], add.inputs[1])
    nt.links.new(add.outputs[0], out.inputs["Surface"])
    return mat


def textured_material(name):
    mat = bpy.data.materials.new(name)
    nt, out = _nodes(mat)
    d = nt.nodes.new("ShaderNodeBsdfDiffuse")
    tex = nt.nodes.new("ShaderNodeTexChecker")
    nt.links.new(tex.outputs["Color"], d.inputs["Color"])
    nt.links.new(d.outputs[0], out.inputs["Surface"])
    mat.diffuse_color = (0.3, 0.4, 0.5, 1.0)
    return mat


def node_world(name):
    """A new world with its node tree (Background, World Output) in use, in every version (5.0
    deprecates use_nodes: worlds always use nodes there)."""
    world = bpy.data.worlds.new(name)
    if bpy.app.version < (5, 0, 0):
        world.use_nodes = True
    return world


def black_world():
    scene = bpy.context.scene
    world = node_world("Black")
    bg = world.node_tree.nodes.get("Background")
    if bg is not None:
        bg.inputs["Strength"].default_value = 0.0
    world.color = (0, 0, 0)
    scene.world = world


def fresh_bake_target(me, name):
    """The FLOAT_COLOR corner attribute `name` of mesh `me`, made or reused, at 0 and active: a
    Cycles bake target as a fresh one (Bevel gives the faces it makes the original index of a
    neighbour it picks by the corner data, colours included, so the values a reused target
    holds would move the corners Cycles bakes)."""
    attr = me.color_attributes.get(name) or me.color_attributes.new(name, "FLOAT_COLOR", "CORNER")
    attr.data.foreach_set("color", np.zeros(len(attr.data) * 4, dtype=np.float32))
    me.color_attributes.active_color = attr
    me.update()
    return attr


def corner_colors(obj, name="Radiosity"):
    me = obj.data
    attr = me.color_attributes.get(name)
    if attr is None:
        return None
    buf = np.empty(len(me.loops) * 4, dtype=np.float32)
    attr.data.foreach_get("color", buf)
    return buf.reshape(-1, 4)


def mesh_colours(scene, name="Radiosity"):
    """{object name: (C, 3) baked colours} of every mesh object of the scene that has them."""
    out = {}
    for o in scene.objects:
        if o.type == "MESH":
            c = corner_colors(o, name)
            if c is not None:
                out[o.name] = c[:, :3].copy()
    return out


def colours_nrmse(a, b):
    """NRMSE of colours `a` against `b` (mesh_colours dicts) over the objects both have."""
    keys = sorted(set(a) & set(b))
    x = np.concatenate([a[k] for k in keys])
    y = np.concatenate([b[k] for k in keys])
    return float(np.sqrt(np.mean((x - y) ** 2)) / np.sqrt(np.mean(y ** 2)))


def color_attr_names(obj):
    return [a.name for a in obj.data.color_attributes]


def bake(**kw):
    """Run the operator; returns (ok, error message or None, reports)."""
    mod = sys.modules[ADDON]
    try:
        res = bpy.ops.radiosity.bake(**kw)
        ok, err = "FINISHED" in res, None
    except RuntimeError as exc:       # bpy.ops raises on an ERROR report
        ok, err = False, str(exc)
    reports = [list(r) for r in mod.bake.last_reports]
    return ok, err, reports


def last_stats():
    text = bpy.context.scene.radiosity.last_stats
    return json.loads(text) if text else None


def native_is_fake():
    from radiosity import radiosity_native
    return bool(getattr(radiosity_native, "FAKE", False))
