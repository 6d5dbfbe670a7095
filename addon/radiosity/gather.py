"""Blender scene -> core.SceneInput (numpy arrays, world space), in bulk with foreach_get.

Rules (see README):
- every object of the view layer with ``visible_get()`` true, ``hide_render`` false and no
  render-disabled collection above it; meshes, curves, surfaces, text and metaballs all enter
  through their evaluated mesh (modifiers applied, via the depsgraph);
- each collection is a native cluster (nested collections nest); objects that sit directly in the
  scene collection get cluster -1; an object in several collections uses its first one;
- only MESH objects can receive colours. They are written to the original mesh data, and are
  skipped with a warning when a modifier changed the corner layout, when the mesh is shared with
  an object baked before (linked duplicates: the first user wins), when it comes from a linked
  library, or when the object is in Edit Mode. Skipped objects still cast and reflect light.
"""
from dataclasses import dataclass

import bpy
import numpy as np

from .core import lights as core_lights
from .core import scene_data
from .core.corners import reverse_polygon_permutation
from .core.scene_data import ObjectInput, SceneInput
from . import textures, world as world_map
from .materials import MaterialTable

GEOMETRY_TYPES = {"MESH", "CURVE", "SURFACE", "FONT", "META"}
# Custom property marking the add-on's own adaptive-mesh output: never gathered as geometry.
ADAPTIVE_TAG = "radiosity_adaptive_of"


@dataclass
class WriteTarget:
    object_name: str
    mesh_name: str


def _walk_collections(view_layer):
    """{collection name_full: parent collection or None} for included, renderable collections."""
    parents = {}

    def walk(layer_coll, parent):
        for child in layer_coll.children:
            coll = child.collection
            if child.exclude or coll.hide_render:
                continue        # excluded or render-off collections cost nothing
            parents[coll.name_full] = (coll, parent)
            walk(child, coll)

    walk(view_layer.layer_collection, None)
    return parents


def _int_array(collection, attr, count):
    out = np.empty(count, dtype=np.int32)
    if count:
        collection.foreach_get(attr, out)
    return out


def _mesh_arrays(me):
    nv, nf, nc = len(me.vertices), len(me.polygons), len(me.loops)
    co = np.empty(nv * 3, dtype=np.float32)
    if nv:
        me.vertices.foreach_get("co", co)
    return (co.reshape(nv, 3),
            _int_array(me.polygons, "loop_start", nf),
            _int_array(me.polygons, "loop_total", nf),
            _int_array(me.polygons, "material_index", nf),
            _int_array(me.loops, "vertex_index", nc))


def _slot_values(obj_eval, materials):
    rho, emis = [], []
    for slot in obj_eval.material_slots:
        r, e = materials.get(slot.material)
        rho.append(r)
        emis.append(e)
    return rho, emis


def _write_target(obj, corner_verts, first_user, warnings):
    """Decide whether obj.data may receive colours; returns WriteTarget or None."""
    if obj.type != "MESH":
        return None     # curves/text/metaballs take part in the solve but have no corners to write
    me = obj.data
    if obj.library is not None or me.library is not None:
        warnings.append(f"object '{obj.name_full}': mesh '{me.name_full}' comes from a linked "
                        f"library (read-only); it lights the scene but is not written")
        return None
    if obj.mode == "EDIT":
        warnings.append(f"object '{obj.name}' is in Edit Mode; leave Edit Mode to bake it")
        return None
    owner = first_user.get(me.name_full)
    if owner is not None:
        warnings.append(f"object '{obj.name}' shares mesh '{me.name}' with '{owner}'; only "
                        f"'{owner}' is baked (linked duplicates get one bake)")
        return None
    if len(me.loops) != len(corner_verts) or not np.array_equal(
            _int_array(me.loops, "vertex_index", len(me.loops)), corner_verts):
        warnings.append(f"object '{obj.name}': a modifier changes its topology ({len(me.loops)} "
                        f"corners before, {len(corner_verts)} after); apply or disable it to "
                        f"bake this object")
        return None
    first_user[me.name_full] = obj.name
    return WriteTarget(obj.name_full, me.name_full)


def _check_material_values(obj, rho, emission, mat_index, slot_names):
    """NaN/inf in a used material's colours or strengths (or a colour x strength past float
    range) refuse the bake, naming the object and the material."""
    for label, arr in (("colour", rho), ("emission (colour x strength)", emission)):
        bad = ~np.isfinite(arr).all(axis=1)
        if bad.any():
            face = int(np.argmax(bad))
            slot = int(np.clip(mat_index[face], 0, max(len(slot_names) - 1, 0)))
            name = slot_names[slot] if slot_names else "(none)"
            raise scene_data.InputError(
                f"object '{obj.name_full}': material '{name}' has a NaN or infinite {label} "
                f"({int(bad.sum())} faces)")


def gather(scene, view_layer, depsgraph):
    """Returns (SceneInput, world matrices {object name_full: 4x4}, warnings)."""
    warnings = []
    si = SceneInput()
    coll_parents = _walk_collections(view_layer)
    cluster_of = {}
    materials = MaterialTable()
    first_user = {}
    matrices = {}
    texture_requests = []     # objects with textured materials, evaluated by Cycles at the end

    def cluster_index(coll):
        key = coll.name_full
        if key not in cluster_of:
            _, parent = coll_parents[key]
            pidx = cluster_index(parent) if parent is not None else -1
            cluster_of[key] = si.add_cluster(coll.name, pidx)
        return cluster_of[key]

    def object_cluster(obj):
        for coll in obj.users_collection:
            if coll == scene.collection:
                return -1
            if coll.name_full in coll_parents:
                return cluster_index(coll)
        return None     # only in excluded / render-disabled collections: not rendered

    for obj in view_layer.objects:
        if obj.type == "LIGHT" and not obj.hide_render and obj.visible_get(view_layer=view_layer) \
                and any(c == scene.collection or c.name_full in coll_parents
                        for c in obj.users_collection):
            _gather_light(obj, object_cluster(obj), si, warnings)
            continue
        if obj.type not in GEOMETRY_TYPES or obj.hide_render or ADAPTIVE_TAG in obj.keys():
            continue
        if not obj.visible_get(view_layer=view_layer):
            continue
        if not any(c == scene.collection or c.name_full in coll_parents
                   for c in obj.users_collection):
            continue
        obj_eval = obj.evaluated_get(depsgraph)
        try:
            me = obj_eval.to_mesh()
        except RuntimeError:
            me = None
        if me is None:
            continue
        try:
            if len(me.polygons) == 0:
                # Edges/points only, an empty curve, or a modifier (Mask, Weld, Boolean...) left
                # nothing: nothing to light, and it costs nothing.
                continue
            co, starts, totals, mat_index, corner_verts = _mesh_arrays(me)
            mat = np.array(obj_eval.matrix_world, dtype=np.float64)
            rho_slots, emis_slots = _slot_values(obj_eval, materials)
            textured_slots = [i for i, s in enumerate(obj_eval.material_slots)
                              if materials.is_textured(s.material)]
            slot_names = [s.material.name if s.material is not None else "(empty slot)"
                          for s in obj_eval.material_slots]
        finally:
            obj_eval.to_mesh_clear()

        if not np.isfinite(mat).all():
            raise scene_data.InputError(
                f"object '{obj.name_full}': its world matrix (location, rotation or scale, its "
                f"own or a parent's) has a NaN or infinite value")
        world = co.astype(np.float64) @ mat[:3, :3].T + mat[:3, 3]
        # A mirroring matrix would flip the winding-derived normal; Blender keeps the visible
        # side, so hand the solver the reversed winding and map results back afterwards.
        perm = None
        if np.linalg.det(mat[:3, :3]) < 0.0:
            perm = reverse_polygon_permutation(starts, totals)
        rho = scene_data.clamp_reflectance(
            scene_data.face_table(rho_slots, mat_index, [scene_data.DEFAULT_REFLECTANCE] * 3))
        emission = scene_data.clamp_emission(
            scene_data.face_table(emis_slots, mat_index, [0.0, 0.0, 0.0]))
        _check_material_values(obj, rho, emission, mat_index, slot_names)
        target = _write_target(obj, corner_verts, first_user, warnings)
        if target is None and obj.type == "MESH":
            si.unwritable.append(obj.name_full)
        # name_full: a linked object may share its name with a local one.
        si.objects.append(ObjectInput(
            name=obj.name_full, cluster=object_cluster(obj), vertices=world, loop_starts=starts,
            loop_totals=totals, corner_verts=corner_verts, reflectance=rho, emission=emission,
            corner_perm=perm, target=target, matrix=mat, local_vertices=co))
        if textured_slots:
            texture_requests.append(textures.Request(len(si.objects) - 1, obj, textured_slots))
        matrices[obj.name_full] = mat
    si.evaluation_stats = textures.evaluate(si, texture_requests, depsgraph, materials, warnings)
    _gather_world(scene, si, warnings)
    warnings.extend(materials.warnings)
    return si, matrices, warnings


def _diffuse_factor(obj, light):
    """The light's diffuse factor (EEVEE's, honoured here; Cycles ignores it), zero when the
    object's ray visibility excludes diffuse rays (Cycles honours that)."""
    f = float(getattr(light, "diffuse_factor", 1.0))
    if not getattr(obj, "visible_diffuse", True):
        f = 0.0
    return f


def _gather_light(obj, cluster, si, warnings):
    light = obj.data
    mat = np.array(obj.matrix_world, dtype=np.float64)
    factor = _diffuse_factor(obj, light)
    color = tuple(light.color)
    name = obj.name_full
    if not np.isfinite(mat).all():
        raise scene_data.InputError(
            f"light '{name}': its world matrix (location, rotation or scale, its own or a "
            f"parent's) has a NaN or infinite value")
    power = float(light.energy)
    if power < 0.0:
        # Cycles would subtract light; a radiosity solution has no negative light.
        warnings.append(f"light '{name}': negative power {power:g} is treated as 0")
        power = 0.0
    version = tuple(bpy.app.version)
    cyc = getattr(light, "cycles", None)
    if cyc is not None and getattr(cyc, "is_portal", False):
        return      # a portal guides sampling; it emits nothing
    if cyc is not None and not getattr(cyc, "cast_shadow", True):
        warnings.append(f"light '{name}': 'Cast Shadow' off is not supported; it casts shadows")
    if light.type == "AREA":
        sy = light.size_y if light.shape in ("RECTANGLE", "ELLIPSE") else light.size
        verts, starts, totals, cverts, area = core_lights.area_light_mesh(
            light.shape, light.size, sy, mat)
        spread = float(getattr(light, "spread", np.pi))
        if spread < np.pi - 1e-4:
            warnings.append(f"light '{name}': spread {np.degrees(spread):.0f} deg is not supported; "
                            f"it emits as a Lambertian surface (180 deg)")
        rad = core_lights.area_radiance(power, color, area, version, factor)
        si.objects.append(scene_data.ObjectInput(
            name=name, cluster=cluster, vertices=verts, loop_starts=starts, loop_totals=totals,
            corner_verts=cverts, reflectance=np.zeros((len(starts), 3), np.float32),
            emission=np.tile(np.asarray(rad, np.float32), (len(starts), 1)), target=None,
            # pinv: a light scaled to 0 has a singular matrix (inv raised LinAlgError)
            matrix=mat, local_vertices=core_lights.transform(verts, np.linalg.pinv(mat)),
            two_sided=np.zeros(len(starts), np.uint8), occluder=False))
        return
    pos = tuple(mat[:3, 3])
    if light.type == "POINT":
        si.lights.append(core_lights.LightInput(
            name, core_lights.POINT, core_lights.point_intensity(power, color, factor),
            position=pos, radius=float(light.shadow_soft_size)))
    elif light.type == "SPOT":
        si.lights.append(core_lights.LightInput(
            name, core_lights.SPOT, core_lights.point_intensity(power, color, factor),
            position=pos, direction=core_lights.direction_of(mat),
            radius=float(light.shadow_soft_size), spot_size=float(light.spot_size),
            spot_blend=float(light.spot_blend),
            spot_cos_falloff=core_lights.spot_cos_falloff(version)))
    elif light.type == "SUN":
        si.lights.append(core_lights.LightInput(
            name, core_lights.SUN, core_lights.sun_irradiance(power, color, factor),
            direction=core_lights.direction_of(mat), angle=float(light.angle)))


def _gather_world(scene, si, warnings):
    """A constant world colour becomes a uniform sky; a world whose background a node tree
    drives (Sky Texture, HDRI, anything) is rendered by Cycles into a map (world.py)."""
    world = scene.world
    if world is None:
        return
    color, strength = tuple(world.color), 1.0
    nt = world.node_tree if getattr(world, "use_nodes", True) else None
    if nt is not None:
        out = next((n for n in nt.nodes if n.bl_idname == "ShaderNodeOutputWorld"
                    and getattr(n, "is_active_output", True)), None)
        surf = out.inputs.get("Surface") if out is not None else None
        if surf is None or not surf.is_linked:
            return          # nothing plugged in: Cycles renders black
        node = surf.links[0].from_node
        plain = node.bl_idname == "ShaderNodeBackground" and not (
            node.inputs["Color"].is_linked or node.inputs["Strength"].is_linked)
        if not plain:
            _gather_world_map(world, si, warnings)
            return
        color = tuple(node.inputs["Color"].default_value)[:3]
        strength = float(node.inputs["Strength"].default_value)
    rad = float(strength) * np.asarray(color[:3], float)
    if not np.isfinite(rad).all():
        raise scene_data.InputError(f"world '{world.name}': the background colour x strength has "
                                    f"a NaN or infinite value")
    if (rad < 0).any():
        warnings.append(f"world '{world.name}': negative background {tuple(rad)} is treated as 0")
        rad = np.maximum(rad, 0.0)
    rad = tuple(float(x) for x in rad)
    if max(rad) > 0:
        si.lights.append(core_lights.LightInput(world.name, core_lights.SKY, rad))


def _gather_world_map(world, si, warnings):
    try:
        env, sun, stats = world_map.render_world(world)
    except Exception as exc:  # noqa: BLE001  (any failure of Blender's render: warn, no light)
        warnings.append(f"world '{world.name}': Cycles could not render it ({exc}); it gives "
                        f"no light")
        return
    si.evaluation_stats = dict(si.evaluation_stats or {}, **stats)
    if sun is not None:
        si.lights.append(sun)
    if float(env.max()) > 0.0:
        si.lights.append(core_lights.LightInput(world.name, core_lights.SKY, (1.0, 1.0, 1.0),
                                                env=env))
