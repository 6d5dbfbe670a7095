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

Before 4.0 the diffuse lobe is Disney's, whose retro-reflection grows with Roughness: under
uniform light and seen along the normal it reflects 0.976 + 0.0595 x roughness of Base Color
(1.006 at the default 0.5, 1.036 at 1; Specular, Clearcoat and Sheen leave it as it is, the
Sheen lobe adds under 0.1 % along the normal). Its COLOR pass is Base Color alone, so here the
factor is measured with light: a grid of quads with the node's Roughness and Sheen and a white
base under a uniform white world, COMBINED bake (the glossy lobes and subsurface set to 0). That
is the output's factor under diffuse light and, by reciprocity, the albedo for light arriving
along the normal. Under uniform light from every side the albedo is higher (1.065 at roughness
1) and under light from along the normal the output is Base Color whole; in a closed room lit
by a lamp this one factor is the closest to Cycles (bench/results/principled_legacy.md).

One bake per distinct parameter set in a Blender session, kept in memory.
"""
import bpy
import numpy as np

from . import textures

# Inputs that do not enter the factor: modelled elsewhere (base colour, metallic, transmission,
# emission: materials.py) or irrelevant to a diffuse colour pass (normals, tangents, weights of
# absent lobes are read anyway: a changed value is just another key).
_SKIP = {"Base Color", "Metallic", "Transmission", "Transmission Weight", "Emission", "Emission Color",
         "Emission Strength", "Normal", "Clearcoat Normal", "Coat Normal", "Tangent", "Alpha", "Weight"}
# Blender 3.x: lobes set to 0 in the lit measurement and left out of its key. Specular and
# Clearcoat lie on top of the diffuse without taking from it (they would only add noise to the
# bake); a subsurface random walk on a single sheet of quads measures what leaks out of its
# back, not an albedo (subsurface is not modelled: materials.py reads Base Color).
_LEGACY_ZERO = {"Specular", "Clearcoat", "Subsurface"}
LEGACY_SAMPLES = 256        # per vertex: the factor's noise stays far below the solver's
LEGACY_GRID = 8             # quads along each side of the measured sheet

_cache = {}
_errors = []


def pop_errors():
    """Messages of measurements that failed since the last call (their factor counts as 1)."""
    out = list(_errors)
    _errors.clear()
    return out


def _legacy():
    return bpy.app.version < (4, 0, 0)


def _key(node, skip):
    items = []
    for sock in node.inputs:
        if sock.name in skip or not hasattr(sock, "default_value"):
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
    Principled BSDF node: Blender 4.0+ what the layers above leave to the diffuse, 3.x the
    retro-reflection of its diffuse lobe. Linked inputs count at their unlinked value."""
    legacy = _legacy()
    key = (legacy,) + _key(node, _SKIP | _LEGACY_ZERO if legacy else _SKIP)
    hit = _cache.get(key)
    if hit is None:
        try:
            hit = _measure(node, legacy)
        except Exception as exc:  # noqa: BLE001  (any failure of Blender's bake: Base Color whole)
            _errors.append(f"the diffuse part of Principled BSDF '{node.name}' could not be measured "
                           f"by Cycles ({exc}); Base Color is used whole")
            hit = np.ones(3)
        _cache[key] = hit
    return hit.copy()


def _sheet(mesh, n):
    """An n x n grid of quads over [-0.5, 0.5]^2 at z = 0, normal +z, into `mesh`."""
    t = np.linspace(-0.5, 0.5, n + 1)
    verts = [(float(x), float(y), 0.0) for y in t for x in t]
    row = n + 1
    faces = [(j * row + i, j * row + i + 1, (j + 1) * row + i + 1, (j + 1) * row + i)
             for j in range(n) for i in range(n)]
    mesh.from_pydata(verts, [], faces)


def _copy_inputs(node, p, skip):
    """The values of `node`'s inputs onto `p`, the measured node, but those in `skip`. One `p`
    cannot take is measured at its default, so the factor may not be the node's: said in
    _errors (the bake's warnings)."""
    for sock in node.inputs:
        dst = p.inputs.get(sock.name)
        if dst is None or sock.name in skip or not hasattr(sock, "default_value"):
            continue
        try:
            dst.default_value = sock.default_value
        except (TypeError, ValueError, AttributeError) as exc:
            _errors.append(f"the diffuse part of Principled BSDF '{node.name}' was measured with "
                           f"its input '{sock.name}' at the default ({exc})")


def _measure(node, legacy=False):
    scene = mesh = obj = mat = world = None
    skip = _SKIP | _LEGACY_ZERO if legacy else _SKIP
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
        _copy_inputs(node, p, skip)
        p.inputs["Base Color"].default_value = (1.0, 1.0, 1.0, 1.0)
        zero = ("Metallic", "Transmission Weight", "Emission Strength")
        if legacy:
            zero += ("Transmission",) + tuple(sorted(_LEGACY_ZERO))
        for name in zero:
            if p.inputs.get(name) is not None:
                p.inputs[name].default_value = 0.0
        nt.links.new(p.outputs[0], out.inputs["Surface"])

        mesh = bpy.data.meshes.new("radiosity_principled_tmp")
        if legacy:
            _sheet(mesh, LEGACY_GRID)
        else:
            mesh.from_pydata([(-0.5, -0.5, 0), (0.5, -0.5, 0), (0.5, 0.5, 0), (-0.5, 0.5, 0)], [], [(0, 1, 2, 3)])
        mesh.materials.append(mat)
        scene = bpy.data.scenes.new("radiosity_principled_tmp")
        textures.set_cycles(scene)
        if legacy:
            # Radiance 1 from every direction: a white Diffuse BSDF bakes 1, so the bake of the
            # white-based Principled is the factor itself.
            world = bpy.data.worlds.new("radiosity_principled_tmp")
            world.use_nodes = True
            bg = world.node_tree.nodes.get("Background")
            bg.inputs["Color"].default_value = (1.0, 1.0, 1.0, 1.0)
            bg.inputs["Strength"].default_value = 1.0
            scene.world = world
            scene.cycles.samples = LEGACY_SAMPLES
        obj = bpy.data.objects.new("radiosity_principled_tmp", mesh)
        scene.collection.objects.link(obj)
        kind = "COMBINED" if legacy else "DIFFUSE"
        textures.bake(scene, scene.view_layers[0], [obj], kind)
        f = textures.colours(mesh, textures.ATTR + kind).mean(axis=0)
        if not np.all(np.isfinite(f)):
            raise RuntimeError(f"the {kind} bake gave a non-finite colour")
        # Disney's diffuse seen along the normal stays below 1.5 (roughness 1, grazing light).
        return np.clip(f, 0.0, 1.5 if legacy else 1.0)
    finally:
        if obj is not None:
            bpy.data.objects.remove(obj, do_unlink=True)
        if mesh is not None:
            bpy.data.meshes.remove(mesh, do_unlink=True)
        if mat is not None:
            bpy.data.materials.remove(mat, do_unlink=True)
        if scene is not None:
            bpy.data.scenes.remove(scene, do_unlink=True)
        if world is not None:
            bpy.data.worlds.remove(world, do_unlink=True)
