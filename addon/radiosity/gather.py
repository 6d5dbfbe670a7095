"""Blender scene -> core.SceneInput (numpy arrays, world space), in bulk with foreach_get.

Rules (see README):
- every object of the view layer with ``visible_get()`` true, ``hide_render`` false and no
  render-disabled collection above it; meshes, curves, surfaces, text and metaballs all enter
  through their evaluated mesh (modifiers applied, via the depsgraph);
- instances (collection instances, geometry-nodes instances, particles, instancing vertices or
  faces) of such an object enter from the depsgraph's ``object_instances``: they cast and
  reflect light but have no colours of their own. All instances of one instancing object form
  one native cluster (they move with it);
- each collection is a native cluster (nested collections nest); objects that sit directly in the
  scene collection get cluster -1; an object in several collections uses its first one;
- only MESH objects can receive colours. They are written to the original mesh data; when a
  modifier changed the corner layout, each original corner takes the value of the evaluated
  corner that maps back to it, as Cycles' bake does (core.corners.original_corner_map). Skipped
  with a warning: a mesh shared with an object baked before (linked duplicates: the first user
  wins), one from a linked library, an object in Edit Mode. Skipped objects still cast and
  reflect light.
"""
from contextlib import contextmanager
from dataclasses import dataclass

import bpy
import numpy as np

from .core import corners as core_corners
from .core import lights as core_lights
from .core import scene_data
from .core import srgb
from .core.corners import reverse_polygon_permutation
from .core.scene_data import ObjectInput, SceneInput
from . import textures, world as world_map
from .materials import MaterialTable

GEOMETRY_TYPES = {"MESH", "CURVE", "SURFACE", "FONT", "META"}
# Custom property marking the add-on's own adaptive-mesh output: never gathered as geometry.
ADAPTIVE_TAG = "radiosity_adaptive_of"
# The original-index attributes (see core.corners): INT8 digits per domain, on the original mesh
# only while the evaluated meshes are read.
ORIGIN_DOMAINS = ("POINT", "FACE")
ORIGIN_ATTR_COUNT = core_corners.ORIGIN_DIGITS + core_corners.CHECK_DIGITS


def _origin_attr_names(domain):
    return [f"__radiosity_origin_{domain.lower()}{k}" for k in range(ORIGIN_ATTR_COUNT)]
PERSISTENT_ID_UNUSED = 2147483647     # INT_MAX pads an instance's persistent_id


@dataclass
class WriteTarget:
    object_name: str
    mesh_name: str


@dataclass
class _Geometry:
    """One evaluated mesh, in object space, with its per-face materials."""
    co: np.ndarray
    starts: np.ndarray
    totals: np.ndarray
    corner_verts: np.ndarray
    reflectance: np.ndarray
    emission: np.ndarray
    vertex_origin: object = None     # per vertex its original vertex or -1; None: not tagged
    face_origin: object = None


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


def _read_origin(me, domain, count):
    """The evaluated mesh's original indices of one domain (core.corners.decode_origin), or
    None when it does not carry the attributes (a modifier dropped them)."""
    arrays = []
    for name in _origin_attr_names(domain):
        a = me.attributes.get(name)
        if a is None or a.domain != domain or len(a.data) != count:
            return None
        values = np.empty(count, np.int32)
        if count:
            a.data.foreach_get("value", values)
        arrays.append(values)
    return core_corners.decode_origin(arrays, count)


def _evaluated_geometry(name, obj_eval, materials):
    """_Geometry of an evaluated object, or None when it has no faces."""
    try:
        me = obj_eval.to_mesh()
    except RuntimeError:
        me = None
    if me is None:
        return None
    try:
        if len(me.polygons) == 0:
            # Edges/points only, an empty curve, or a modifier (Mask, Weld, Boolean...) left
            # nothing: nothing to light, and it costs nothing.
            return None
        co, starts, totals, mat_index, corner_verts = _mesh_arrays(me)
        rho_slots, emis_slots = _slot_values(obj_eval, materials)
        slot_names = [s.material.name if s.material is not None else "(empty slot)"
                      for s in obj_eval.material_slots]
        vo = _read_origin(me, "POINT", len(me.vertices))
        fo = _read_origin(me, "FACE", len(me.polygons))
    finally:
        obj_eval.to_mesh_clear()
    rho = scene_data.clamp_reflectance(
        scene_data.face_table(rho_slots, mat_index, [scene_data.DEFAULT_REFLECTANCE] * 3))
    emission = scene_data.clamp_emission(
        scene_data.face_table(emis_slots, mat_index, [0.0, 0.0, 0.0]))
    _check_material_values(name, rho, emission, mat_index, slot_names)
    return _Geometry(co, starts, totals, corner_verts, rho, emission, vo, fo)


def _needs_origin(obj):
    """A local mesh object out of Edit Mode with modifiers: its corners may need mapping."""
    return (obj.type == "MESH" and obj.library is None and obj.data.library is None
            and obj.mode != "EDIT" and len(obj.modifiers) > 0 and len(obj.data.polygons) > 0)


def _color_values(attr):
    """A corner colour attribute's values and the property they were read from: a byte colour
    through its sRGB bytes, which round-trip exactly."""
    prop = "color_srgb" if attr.data_type == "BYTE_COLOR" else "color"
    values = np.empty(len(attr.data) * 4, dtype=np.float32)
    attr.data.foreach_get(prop, values)
    return prop, values


@contextmanager
def _origin_layers(objects, depsgraph, own_attributes=()):
    """For the time of the block, the meshes of `objects` carry the original-index attributes
    (_origin_attr_names) and the depsgraph is evaluated with them; afterwards the attributes are
    removed again (the meshes are as they were; Blender re-evaluates them when next needed).

    Bevel picks the face whose attributes (and original index) a new face takes from the
    corner data, colours included, so the corner map would follow the values of our own
    output attributes (`own_attributes`) from the last bake: they read as zero (as a fresh
    bake target does) while the block lasts, and get their values back after."""
    tagged = []
    saved = []
    try:
        for obj in objects:
            me = obj.data
            if any(me.as_pointer() == t.as_pointer() for t in tagged):
                continue        # a mesh shared by several objects: once
            tagged.append(me)
            for name in own_attributes:
                attr = me.color_attributes.get(name)
                if attr is None or attr.domain != "CORNER":
                    continue
                prop, values = _color_values(attr)
                saved.append((me, name, prop, values))
                attr.data.foreach_set(prop, np.zeros_like(values))
            for domain in ORIGIN_DOMAINS:
                n = len(me.vertices) if domain == "POINT" else len(me.polygons)
                for name, values in zip(_origin_attr_names(domain),
                                        core_corners.origin_digits(n)):
                    old = me.attributes.get(name)
                    if old is not None:
                        me.attributes.remove(old)
                    me.attributes.new(name, "INT8", domain).data.foreach_set(
                        "value", values.astype(np.int32))
        if tagged:
            depsgraph.update()
        yield
    finally:
        try:
            for me, name, prop, values in reversed(saved):
                me.color_attributes[name].data.foreach_set(prop, values)
        finally:
            for me in tagged:
                for domain in ORIGIN_DOMAINS:
                    for name in _origin_attr_names(domain):
                        attr = me.attributes.get(name)
                        if attr is not None:
                            me.attributes.remove(attr)


def _corner_map(obj, geo, warnings):
    """Per corner of obj.data the corner of the evaluated geometry `geo` it takes its value
    from, or None when the corner layouts are equal (no mapping needed)."""
    me = obj.data
    nc = len(me.loops)
    orig_cv = _int_array(me.loops, "vertex_index", nc)
    if nc == len(geo.corner_verts) and np.array_equal(orig_cv, geo.corner_verts):
        return None
    nf, nv = len(me.polygons), len(me.vertices)
    starts = _int_array(me.polygons, "loop_start", nf)
    totals = _int_array(me.polygons, "loop_total", nf)
    face_origin = geo.face_origin
    if geo.vertex_origin is not None and face_origin is not None:
        cmap = core_corners.original_corner_map(
            starts, totals, orig_cv, nv, geo.totals, geo.corner_verts, face_origin,
            geo.vertex_origin)
    else:
        cmap = np.full(nc, -1, dtype=np.int64)
    if (cmap < 0).any():
        co = np.empty(nv * 3, np.float32)
        me.vertices.foreach_get("co", co)
        co = co.reshape(nv, 3)
    if (cmap < 0).any() and face_origin is not None:
        # A face made from the corner's face, but no vertex from its vertex (a modifier
        # rebuilt the vertices: Decimate, Weld): the nearest corner of those faces.
        n = core_corners.match_in_face(cmap, totals, orig_cv, co, geo.totals,
                                       geo.corner_verts, geo.co, face_origin)
        if n:
            warnings.append(f"object '{obj.name}': for {n} of its {nc} corners no evaluated "
                            f"vertex comes from the corner's vertex; they take the nearest "
                            f"corner of the faces made from theirs")
    if (cmap < 0).any():
        # No evaluated face maps back (a modifier rebuilt the surface: Remesh, Boolean,
        # geometry nodes): the evaluated vertex nearest to the corner's vertex stands in.
        from mathutils.kdtree import KDTree
        tree = KDTree(len(geo.co))
        for i, p in enumerate(geo.co):
            tree.insert(p, i)
        tree.balance()
        need = np.unique(orig_cv[cmap < 0])
        nearest = np.full(nv, -1, dtype=np.int64)
        for v in need:
            nearest[v] = tree.find(co[v])[1]
        n = core_corners.fill_unmatched(cmap, orig_cv, nearest, geo.corner_verts)
        warnings.append(f"object '{obj.name}': {n} of its {nc} corners have no counterpart in "
                        f"the mesh its modifiers make; they take the value of the nearest "
                        f"evaluated vertex")
    return cmap


def _write_target(obj, first_user, warnings):
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
    first_user[me.name_full] = obj.name
    return WriteTarget(obj.name_full, me.name_full)


def _check_material_values(name, rho, emission, mat_index, slot_names):
    """NaN/inf in a used material's colours or strengths (or a colour x strength past float
    range) refuse the bake, naming the object and the material."""
    for label, arr in (("colour", rho), ("emission (colour x strength)", emission)):
        bad = ~np.isfinite(arr).all(axis=1)
        if bad.any():
            face = int(np.argmax(bad))
            slot = int(np.clip(mat_index[face], 0, max(len(slot_names) - 1, 0)))
            slot_name = slot_names[slot] if slot_names else "(none)"
            raise scene_data.InputError(
                f"object '{name}': material '{slot_name}' has a NaN or infinite {label} "
                f"({int(bad.sum())} faces)")


def _object_input(name, geo, mat, cluster, target=None, corner_map=None, instance_of=None):
    if not np.isfinite(mat).all():
        raise scene_data.InputError(
            f"object '{name}': its world matrix (location, rotation or scale, its "
            f"own or a parent's) has a NaN or infinite value")
    world = geo.co.astype(np.float64) @ mat[:3, :3].T + mat[:3, 3]
    # A mirroring matrix would flip the winding-derived normal; Blender keeps the visible
    # side, so hand the solver the reversed winding and map results back afterwards.
    perm = None
    if np.linalg.det(mat[:3, :3]) < 0.0:
        perm = reverse_polygon_permutation(geo.starts, geo.totals)
    # name_full: a linked object may share its name with a local one. Only what is written
    # (a target) is gathered at its corners: instances, curves and unwritable meshes only
    # light the others.
    return ObjectInput(
        name=name, cluster=cluster, vertices=world, loop_starts=geo.starts,
        loop_totals=geo.totals, corner_verts=geo.corner_verts, reflectance=geo.reflectance,
        emission=geo.emission, corner_perm=perm, target=target, matrix=mat,
        local_vertices=geo.co, corner_map=corner_map, instance_of=instance_of,
        output=target is not None)


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

    def rendered(obj):
        return (not obj.hide_render and obj.visible_get(view_layer=view_layer)
                and any(c == scene.collection or c.name_full in coll_parents
                        for c in obj.users_collection))

    shown = [obj for obj in view_layer.objects if rendered(obj)]
    # An instancer (vertices, faces, particles) hidden in renders shows only its instances.
    geometry = {obj.name_full for obj in shown if obj.type in GEOMETRY_TYPES
                and ADAPTIVE_TAG not in obj.keys()
                and not (obj.is_instancer and not obj.show_instancer_for_render)}
    # (No settings when the add-on's modules run unregistered, as bench/export_scene.py does.)
    own = getattr(scene, "radiosity", None)
    own = (own.attribute_name, srgb.byte_attribute_name(own.attribute_name)) if own else ()
    with _origin_layers([o for o in shown if o.name_full in geometry and _needs_origin(o)],
                        depsgraph, own):
        for obj in shown:
            if obj.type == "LIGHT":
                _gather_light(obj, object_cluster(obj), si, warnings)
                continue
            if obj.name_full not in geometry:
                continue
            obj_eval = obj.evaluated_get(depsgraph)
            geo = _evaluated_geometry(obj.name_full, obj_eval, materials)
            if geo is None:
                continue
            mat = np.array(obj_eval.matrix_world, dtype=np.float64)
            target = _write_target(obj, first_user, warnings)
            cmap = _corner_map(obj, geo, warnings) if target is not None else None
            if target is None and obj.type == "MESH":
                si.unwritable.append(obj.name_full)
            si.objects.append(_object_input(obj.name_full, geo, mat, object_cluster(obj),
                                            target, cmap))
            textured_slots = [i for i, slot in enumerate(obj_eval.material_slots)
                              if materials.is_textured(slot.material)]
            if textured_slots:
                texture_requests.append(textures.Request(len(si.objects) - 1, obj, textured_slots))
            si.scene_objects += 1
            matrices[obj.name_full] = mat
        _gather_instances(depsgraph, {o.name_full: o for o in shown}, object_cluster, si,
                          materials, matrices)
    if si.instancers:
        n = si.instance_count
        names = ", ".join(f"'{k}'" for k in list(si.instancers)[:5]) + \
            (" …" if len(si.instancers) > 5 else "")
        warnings.append(f"{n} instance{'s' if n != 1 else ''} (of {names}) cast and reflect light "
                        f"but get no colours: an instance has no colour attribute of its own "
                        f"(the instanced mesh is baked where it is a real object)")
    # Textured materials: evaluated by Cycles on copies of the evaluated meshes (textures.py),
    # after the original-index attributes are gone again.
    si.evaluation_stats = textures.evaluate(si, texture_requests, depsgraph, materials, warnings)
    _gather_world(scene, si, warnings)
    warnings.extend(materials.warnings)
    return si, matrices, warnings


def _gather_instances(depsgraph, shown, object_cluster, si, materials, matrices):
    """Every instance the depsgraph makes of a shown object: an occluder and reflector, in one
    native cluster per instancing object."""
    clusters = {}
    cache = {}      # evaluated mesh data and materials -> _Geometry: many instances, one read
    for inst in depsgraph.object_instances:
        if not inst.is_instance or inst.parent is None:
            continue
        parent = shown.get(inst.parent.original.name_full)
        if parent is None:
            continue            # its instancer is hidden, render-disabled or excluded
        ob = inst.object
        if ob.type not in GEOMETRY_TYPES:
            continue
        src = ob.original
        if src is not None and src != parent and src.hide_render \
                and parent.instance_type == "COLLECTION":
            continue            # render-disabled objects of an instanced collection: not rendered
        pid = tuple(inst.persistent_id)
        if src == parent and parent.type != "MESH" and \
                all(x == PERSISTENT_ID_UNUSED for x in pid[1:]):
            continue            # a curve's, text's or metaball's own surface: gathered above
        slots = tuple(s.material.name_full if s.material is not None else ""
                      for s in ob.material_slots)
        key = (ob.type, ob.data.as_pointer() if ob.data is not None else ob.as_pointer(), slots)
        if key not in cache:
            cache[key] = _evaluated_geometry(f"{parent.name_full}: instance of {ob.name}", ob,
                                             materials)
        geo = cache[key]
        if geo is None:
            continue
        # Geometry-nodes instances of plain geometry come as temporary objects named after
        # the instancer: their mesh names them.
        label = src.name_full if src is not None and src != parent else \
            (ob.data.name if ob.data is not None else ob.name)
        pid = ".".join(str(x) for x in pid if x != PERSISTENT_ID_UNUSED)
        name = f"{parent.name_full}/{label}#{pid}"
        pname = parent.name_full
        if pname not in clusters:
            clusters[pname] = si.add_cluster(f"{parent.name} (instances)", object_cluster(parent))
        mat = np.array(inst.matrix_world, dtype=np.float64)
        # A copy per instance: the vertices are the same object-space arrays.
        si.objects.append(_object_input(name, geo, mat, clusters[pname], instance_of=pname))
        si.instancers[pname] = si.instancers.get(pname, 0) + 1
        # Moving the instancer moves its instances: the live re-bake watches it.
        matrices[pname] = np.array(parent.matrix_world, dtype=np.float64)


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
            two_sided=np.zeros(len(starts), np.uint8), occluder=False, output=False))
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
