"""The diffuse part of a Principled BSDF as Cycles renders it, per parameter set.

Since Blender 4.0 (Principled v2) Cycles layers the dielectric specular (and coat and sheen)
over the diffuse base and takes from the diffuse what those layers reflect: the diffuse part is
Base Color x a factor below 1 (0.963 with the default roughness 0.5, IOR 1.5 and specular IOR
level 0.5), where Blender 3.x adds the specular on top and leaves Base Color whole. The factor
depends on the other inputs through Cycles' own albedo tables, so it is measured the way Cycles
defines it: a one-quad Cycles bake of type DIFFUSE, COLOR pass only, of a Principled BSDF with
the same inputs and a white base (the factor does not depend on the base colour). Cycles bakes
with the view along the normal, as it bakes every corner, so the factor is exact for the output
and the normal-incidence value for the light transport (grazing views see a little more
specular and a little less diffuse).

One bake per distinct parameter set in a Blender session (about 0.1-0.3 s), kept in memory.
"""
import bpy
import numpy as np

from . import textures

# Inputs that do not enter the factor: modelled elsewhere (base colour, metallic, transmission,
# emission: materials.py) or irrelevant to a diffuse colour pass (normals, tangents, weights of
# absent lobes are read anyway: a changed value is just another key).
_SKIP = {"Base Color", "Metallic", "Transmission", "Transmission Weight", "Emission", "Emission Color",
         "Emission Strength", "Normal", "Clearcoat Normal", "Coat Normal", "Tangent", "Alpha", "Weight"}

_cache = {}
_errors = []


def pop_errors():
    """Messages of measurements that failed since the last call (their factor counts as 1)."""
    out = list(_errors)
    _errors.clear()
    return out


def _key(node):
    items = []
    for sock in node.inputs:
        if sock.name in _SKIP or not hasattr(sock, "default_value"):
            continue
        v = sock.default_value
        try:
            v = tuple(round(float(x), 6) for x in v)
        except TypeError:
            v = round(float(v), 6) if isinstance(v, (int, float)) else str(v)
        items.append((sock.identifier, v))
    for attr in ("distribution", "subsurface_method"):
        items.append((attr, getattr(node, attr, None)))
    return tuple(items)


def diffuse_factor(node):
    """Per-channel factor (3,) on Base Color x (1 - metallic) x (1 - transmission) for a
    Principled BSDF node: 1 before Blender 4.0. Linked inputs count at their unlinked value."""
    if bpy.app.version < (4, 0, 0):
        return np.ones(3)
    key = _key(node)
    hit = _cache.get(key)
    if hit is None:
        try:
            hit = _measure(node)
        except Exception as exc:  # noqa: BLE001  (any failure of Blender's bake: Base Color whole)
            _errors.append(f"the diffuse part of Principled BSDF '{node.name}' could not be measured "
                           f"by Cycles ({exc}); Base Color is used whole")
            hit = np.ones(3)
        _cache[key] = hit
    return hit.copy()


def _measure(node):
    scene = mesh = obj = mat = None
    try:
        mat = bpy.data.materials.new("radiosity_principled_tmp")
        if bpy.app.version < (5, 0, 0):
            mat.use_nodes = True
        nt = mat.node_tree
        nt.nodes.clear()
        out = nt.nodes.new("ShaderNodeOutputMaterial")
        p = nt.nodes.new("ShaderNodeBsdfPrincipled")
        for attr in ("distribution", "subsurface_method"):
            if hasattr(node, attr):
                setattr(p, attr, getattr(node, attr))
        for sock in node.inputs:
            dst = p.inputs.get(sock.name)
            if dst is None or sock.name in _SKIP or not hasattr(sock, "default_value"):
                continue
            try:
                dst.default_value = sock.default_value
            except (TypeError, ValueError, AttributeError):
                pass
        p.inputs["Base Color"].default_value = (1.0, 1.0, 1.0, 1.0)
        for name in ("Metallic", "Transmission Weight", "Emission Strength"):
            if p.inputs.get(name) is not None:
                p.inputs[name].default_value = 0.0
        nt.links.new(p.outputs[0], out.inputs["Surface"])

        mesh = bpy.data.meshes.new("radiosity_principled_tmp")
        mesh.from_pydata([(-0.5, -0.5, 0), (0.5, -0.5, 0), (0.5, 0.5, 0), (-0.5, 0.5, 0)], [], [(0, 1, 2, 3)])
        mesh.materials.append(mat)
        scene = bpy.data.scenes.new("radiosity_principled_tmp")
        textures.set_cycles(scene)
        obj = bpy.data.objects.new("radiosity_principled_tmp", mesh)
        scene.collection.objects.link(obj)
        textures.bake(scene, scene.view_layers[0], [obj], "DIFFUSE")
        f = textures.colours(mesh, textures.ATTR + "DIFFUSE").mean(axis=0)
        if not np.all(np.isfinite(f)):
            raise RuntimeError("the DIFFUSE bake gave a non-finite colour")
        return np.clip(f, 0.0, 1.0)
    finally:
        if obj is not None:
            bpy.data.objects.remove(obj, do_unlink=True)
        if mesh is not None:
            bpy.data.meshes.remove(mesh, do_unlink=True)
        if mat is not None:
            bpy.data.materials.remove(mat, do_unlink=True)
        if scene is not None:
            bpy.data.scenes.remove(scene, do_unlink=True)
