"""Textured materials: what a node tree evaluates to at the surface, evaluated by Cycles.

A material with no constant value (a texture, a colour attribute, a mix driven by a texture,
a group, ...; materials.py calls these "textured") is evaluated by Cycles itself, so any node
tree Cycles can render is understood exactly as Cycles understands it:

- per corner, for the output: a Cycles bake of type DIFFUSE with only the COLOR pass (the
  diffuse albedo, what the COMBINED bake multiplies the irradiance by) and of type EMIT (only
  when the tree can emit) to a colour attribute of a copy of the evaluated mesh. Cycles
  evaluates a corner at its vertex with the corner's attributes (UVs), as its COMBINED bake
  does, so the output's radiance = albedo x irradiance + emission there is Cycles' own.
- per polygon, for the light transport: the area mean over a copy of the mesh whose polygons
  are cut into up to 8 x 8 pieces (n-gons triangulated first), baked the same way: a checker
  on a single quad has the same colour at its four corners, the mean needs points inside. The
  pieces themselves (centroid, area, value) go to the solver too, whose elements take the mean
  of the pieces inside them (a quad refined along a checker's edge: red and white halves).

Everything happens in a temporary scene (its own Cycles settings, the copies, the colour
attributes) that is deleted before returning, whatever happens: the user's scene, objects,
meshes and materials are only read. Cost: one Cycles session per bake type (its set-up) plus
the corners and pieces.

Limits: texture coordinates that depend on the original object (Generated coordinates of an
object whose modifiers move it, Object Info, the object's own attributes the evaluated copy
drops) are those of the evaluated copy; the per-polygon value is a mean over at most 8 x 8
pieces per polygon (fewer on large meshes: at most about PIECE_BUDGET pieces in all), so a
texture much finer than that averages with a small error. Non-diffuse parts (glossy, glass)
count as Cycles' DIFFUSE COLOR pass counts them: not at all.
"""
import hashlib
import time

import bmesh
import bpy
import numpy as np

from . import eval_cache
from .core import scene_data

ATTR = "radiosity_eval"
ORIG = "radiosity_face"
PIECE_BUDGET = 50_000       # pieces (polygons of the cut copies) of all textured objects together
MAX_CUTS = 7                # 8 x 8 pieces per quad at most


def _emits(tree, depth=0):
    """Whether a node tree may emit light (an Emission node, a Principled BSDF with emission,
    or a group that holds one): only then is the EMIT bake worth its cost."""
    if tree is None or depth > 16:
        return False
    for node in tree.nodes:
        if node.type == "EMISSION":
            return True
        if node.type == "BSDF_PRINCIPLED":
            s = node.inputs.get("Emission Strength")
            c = node.inputs.get("Emission Color") or node.inputs.get("Emission")
            strong = s is None or s.is_linked or float(s.default_value) != 0.0
            coloured = c is None or c.is_linked or max(tuple(c.default_value)[:3]) > 0.0
            if strong and coloured:
                return True
        if node.type == "GROUP" and _emits(node.node_tree, depth + 1):
            return True
    return False


def set_cycles(scene):
    """A temporary scene set up for Cycles bakes to colour attributes (also principled.py)."""
    scene.render.engine = "CYCLES"
    c = scene.cycles
    c.device = "CPU"
    c.samples = 1
    c.use_adaptive_sampling = False
    c.use_denoising = False
    c.seed = 0
    scene.render.bake.target = "VERTEX_COLORS"
    scene.render.bake.use_selected_to_active = False


def _cut(me, cuts):
    """Cut every polygon of `me` into pieces (grid fill), each piece keeping its polygon's index
    in the integer face attribute ORIG."""
    bm = bmesh.new()
    try:
        bm.from_mesh(me)
        layer = bm.faces.layers.int.new(ORIG)
        bm.faces.ensure_lookup_table()
        for f in bm.faces:
            f[layer] = f.index
        ngons = [f for f in bm.faces if len(f.verts) > 4]
        if ngons:
            bmesh.ops.triangulate(bm, faces=ngons)
        if cuts > 0:
            bmesh.ops.subdivide_edges(bm, edges=bm.edges[:], cuts=cuts, use_grid_fill=True)
        bm.to_mesh(me)
    finally:
        bm.free()


def colours(me, name):
    attr = me.color_attributes[name]
    out = np.empty(len(me.loops) * 4, dtype=np.float32)
    attr.data.foreach_get("color", out)
    return out.reshape(-1, 4)[:, :3].astype(np.float64)


def _pieces(me):
    """The pieces of a cut copy: per piece its original polygon, its centroid and area in
    object space (kept with the evaluation, which a move does not redo: _apply places them;
    areas only weigh pieces of one polygon against each other, which an affine map keeps),
    and a function giving the mean of a corner layer's values over each piece."""
    n = len(me.polygons)
    starts = np.empty(n, np.int32)
    totals = np.empty(n, np.int32)
    areas = np.empty(n, np.float64)
    orig = np.empty(n, np.int32)
    me.polygons.foreach_get("loop_start", starts)
    me.polygons.foreach_get("loop_total", totals)
    me.polygons.foreach_get("area", areas)
    me.attributes[ORIG].data.foreach_get("value", orig)
    co = np.empty(len(me.vertices) * 3, np.float64)
    me.vertices.foreach_get("co", co)
    lv = np.empty(len(me.loops), np.int32)
    me.loops.foreach_get("vertex_index", lv)

    def mean(corner_values):
        return np.add.reduceat(corner_values, starts, axis=0) / totals[:, None]

    return orig, mean(co.reshape(-1, 3)[lv]), areas, mean


def _face_means(orig, areas, piece, polygons):
    """Area mean per original polygon of the pieces' values `piece`."""
    total = np.zeros((polygons, 3))
    weight = np.zeros(polygons)
    np.add.at(total, orig, piece * areas[:, None])
    np.add.at(weight, orig, areas)
    # Polygons of zero area: the plain mean of their pieces' corners.
    plain = np.zeros((polygons, 3))
    count = np.zeros(polygons)
    np.add.at(plain, orig, piece)
    np.add.at(count, orig, 1.0)
    out = np.where(weight[:, None] > 0, total / np.maximum(weight, 1e-300)[:, None],
                   plain / np.maximum(count, 1.0)[:, None])
    return out


class Request:
    """One gathered object (SceneInput index) with textured material slots."""

    def __init__(self, index, obj, slots):
        self.index = index
        self.obj = obj          # the original object (evaluated again through the depsgraph)
        self.slots = slots      # material slot indices that are textured


def bake(tmp, view_layer, objs, kind):
    """Cycles bake of `kind` (DIFFUSE: its COLOR pass only) of `objs` into a new corner colour
    attribute ATTR + kind of each (also principled.py)."""
    for o in objs:
        me = o.data
        attr = me.color_attributes.new(ATTR + kind, "FLOAT_COLOR", "CORNER")
        me.color_attributes.active_color = attr
        o.select_set(True, view_layer=view_layer)
    view_layer.objects.active = objs[0]
    kwargs = {"type": kind}
    if kind == "DIFFUSE":
        kwargs["pass_filter"] = {"COLOR"}
    with bpy.context.temp_override(scene=tmp, view_layer=view_layer, active_object=objs[0],
                                   object=objs[0], selected_objects=list(objs),
                                   selected_editable_objects=list(objs)):
        result = bpy.ops.object.bake(**kwargs)
    if "FINISHED" not in result:
        raise RuntimeError(f"Cycles' {kind} bake did not finish ({result})")


def _request_key(r, obj_eval, exclude_prefix):
    """What the evaluation of one object reads (eval_cache.py)."""
    h = hashlib.blake2b(digest_size=20)
    placed = False
    for i, slot in enumerate(obj_eval.material_slots):
        mat = slot.material
        tree = mat.node_tree if mat is not None else None
        h.update(f"S|{i}|{mat.name_full if mat else None}|{eval_cache.tree_key(tree)}|"
                 f"{tuple(mat.diffuse_color) if mat else None}".encode())
        placed = placed or eval_cache.reads_placement(tree)
    me = obj_eval.to_mesh()
    try:
        eval_cache.mesh_key(me, h, exclude_prefix)
    finally:
        obj_eval.to_mesh_clear()
    if placed:
        h.update(np.array(obj_eval.matrix_world, dtype=np.float64).tobytes())
    h.update(f"{sorted(r.slots)}|{bpy.app.version_string}".encode())
    return "T" + h.hexdigest()


def _apply(o, slots, mi, values):
    """Set the textured polygons' area means and every corner's value of one object from
    `values` {kind: (corners (C,3), means (F,3))}."""
    face_of = np.repeat(np.arange(o.polygon_count), o.loop_totals)
    textured = np.isin(mi, np.asarray(slots, dtype=np.int64))
    sel = textured[face_of]
    o.texture_pieces = None
    for kind, entry in values.items():
        if kind == "pieces":
            face, local, area, value, emitted = entry
            keep = textured[face]
            if keep.any():
                m = np.eye(4) if o.matrix is None else np.asarray(o.matrix, dtype=np.float64)
                pos = local[keep] @ m[:3, :3].T + m[:3, 3]      # placed as the vertices are
                o.texture_pieces = (face[keep].astype(np.int32), pos, area[keep],
                                    scene_data.clamp_reflectance(value[keep]),
                                    None if emitted is None else scene_data.clamp_emission(emitted[keep]))
            continue
        corners, means = entry
        name, clamp = (("reflectance", scene_data.clamp_reflectance) if kind == "DIFFUSE"
                       else ("emission", scene_data.clamp_emission))
        per_face = getattr(o, name).astype(np.float64)
        per_face[textured] = means[textured]
        setattr(o, name, clamp(per_face))
        per_corner = getattr(o, name)[face_of].astype(np.float64)
        per_corner[sel] = corners[sel]
        setattr(o, "corner_" + name, clamp(per_corner))


class _Scratch:
    """What an evaluation makes in bpy.data (a scene, objects, meshes), removed by free()."""

    def __init__(self):
        self.scene = None
        self.objects, self.meshes = [], []

    def free(self):
        for o in self.objects:
            bpy.data.objects.remove(o, do_unlink=True)
        for me in self.meshes:
            bpy.data.meshes.remove(me, do_unlink=True)
        if self.scene is not None:
            bpy.data.scenes.remove(self.scene, do_unlink=True)


def evaluate(si, requests, depsgraph, materials, warnings):
    """Fill corner_reflectance / corner_emission and the textured polygons' area means of the
    objects in `requests` (SceneInput indices). Returns stats {"textured_objects",
    "textures_baked", "texture_pieces", "texture_seconds"}; on failure the viewport colours stay,
    with one warning per material. Evaluations are kept (eval_cache.py): an object whose
    materials and evaluated mesh did not change is not baked again."""
    if not requests:
        return {}
    t0 = time.perf_counter()
    props = getattr(depsgraph.scene, "radiosity", None)
    exclude = getattr(props, "attribute_name", "Radiosity") or "Radiosity"
    scratch = _Scratch()
    pieces = 0
    try:
        todo, same = _from_cache(si, requests, depsgraph, exclude)
        if todo:
            pieces = _bake_todo(si, todo, same, depsgraph, scratch)
    except Exception as exc:  # noqa: BLE001  (any failure of Blender's bake: fall back, warn)
        _fall_back(si, requests, materials, warnings, exc)
        return {}
    finally:
        scratch.free()
    return {"textured_objects": len(requests), "textures_baked": len(todo),
            "texture_pieces": pieces, "texture_seconds": round(time.perf_counter() - t0, 4)}


def _from_cache(si, requests, depsgraph, exclude):
    """Applies the kept evaluations; returns the requests left to bake, `todo` [(request,
    evaluated object, key)], and `same` [(request, key)]: those whose key one in `todo` has
    too (the same mesh and materials: a room's floor and its copy in the next room) take that
    one's values, baked once, so what a later bake reads from the cache is what this one used."""
    todo, same = [], []
    for r in requests:
        obj_eval = r.obj.evaluated_get(depsgraph)
        key = _request_key(r, obj_eval, exclude)
        hit = eval_cache.get(key)
        if hit is not None and len(hit[0]) == si.objects[r.index].polygon_count:
            _apply(si.objects[r.index], r.slots, hit[0], hit[1])
        elif any(k == key for _, _, k in todo):
            same.append((r, key))
        else:
            todo.append((r, obj_eval, key))
    return todo, same


def _bake_todo(si, todo, same, depsgraph, scratch):
    """Bakes the objects of `todo` in a scratch scene, keeps and applies their values (and
    those of `same`); returns how many pieces were baked."""
    total_faces = sum(si.objects[r.index].polygon_count for r, _, _ in todo)
    k = int(np.sqrt(PIECE_BUDGET / max(total_faces, 1)))
    cuts = int(np.clip(k - 1, 0, MAX_CUTS))
    scratch.scene = bpy.data.scenes.new("radiosity_textures_tmp")
    set_cycles(scratch.scene)
    view_layer = scratch.scene.view_layers[0]
    plain, cut, emit, pieces = _copies(si, todo, depsgraph, scratch, cuts)
    kinds = ["DIFFUSE"] + (["EMIT"] if emit else [])
    for kind in kinds:
        bake(scratch.scene, view_layer, plain + cut, kind)
    baked = {}
    for n, (r, _, key) in enumerate(todo):
        o = si.objects[r.index]
        mi, values = _baked_values(o, plain[n], cut[n] if cut else None, kinds)
        eval_cache.put(key, (mi, values))
        baked[key] = (mi, values)
        _apply(o, r.slots, mi, values)
    for r, key in same:
        _apply(si.objects[r.index], r.slots, *baked[key])
    return pieces


def _copies(si, todo, depsgraph, scratch, cuts):
    """Per object of `todo` a copy of its evaluated mesh in the scratch scene (`plain`) and,
    with cuts, one more cut into pieces (`cut`); also whether any of their materials may emit
    and how many pieces there are."""
    plain, cut, emit, pieces = [], [], False, 0
    for r, obj_eval, _ in todo:
        me, emits = _mesh_copy(obj_eval, depsgraph, scratch)
        emit = emit or emits
        if len(me.loops) != si.objects[r.index].corner_count:
            raise RuntimeError(f"object '{r.obj.name}': the evaluated mesh changed while "
                               f"baking its textures")
        pairs = [(me, plain)]
        if cuts > 0:
            me2 = me.copy()
            scratch.meshes.append(me2)
            _cut(me2, cuts)
            pieces += len(me2.polygons)
            pairs.append((me2, cut))
        else:
            pieces += len(me.polygons)     # big meshes: the corners' mean is the mean
        for mesh, dst in pairs:
            o = bpy.data.objects.new("radiosity_textures_tmp", mesh)
            scratch.objects.append(o)
            o.matrix_world = obj_eval.matrix_world
            scratch.scene.collection.objects.link(o)
            dst.append(o)
    return plain, cut, emit, pieces


def _mesh_copy(obj_eval, depsgraph, scratch):
    """A new mesh of the evaluated object with its effective materials (object-linked slots
    included), and whether any of those may emit."""
    me = bpy.data.meshes.new_from_object(obj_eval, preserve_all_data_layers=True,
                                         depsgraph=depsgraph)
    scratch.meshes.append(me)
    me.materials.clear()
    emit = False
    for slot in obj_eval.material_slots:
        me.materials.append(slot.material)
        if slot.material is not None and slot.material.node_tree is not None:
            emit = emit or _emits(slot.material.node_tree)
    return me, emit


def _baked_values(o, plain, cut, kinds):
    """One object's material indices and baked values {kind: (corners (C,3), means (F,3))},
    with "pieces" from its cut copy `cut` (None: no cut copy, the means are the corners')."""
    values = {}
    per_piece = {}
    if cut is not None:
        orig, centroid, areas, piece_mean = _pieces(cut.data)
    for kind in kinds:
        corners = colours(plain.data, ATTR + kind)
        if cut is not None:
            per_piece[kind] = piece_mean(colours(cut.data, ATTR + kind))
            means = _face_means(orig, areas, per_piece[kind], o.polygon_count)
        else:
            means = np.add.reduceat(corners, o.loop_starts, axis=0) / o.loop_totals[:, None]
        values[kind] = (corners, means)
    if cut is not None:
        values["pieces"] = (orig, centroid, areas, per_piece["DIFFUSE"], per_piece.get("EMIT"))
    return _material_index(plain.data), values


def _fall_back(si, requests, materials, warnings, exc):
    """After a failed evaluation: a warning per textured material and one saying why, and the
    requested objects keep their viewport colours."""
    for why in materials.textured.values():
        warnings.append(why)
    warnings.append(f"textured materials could not be evaluated by Cycles ({exc}); their "
                    f"viewport colours are used")
    for r in requests:
        o = si.objects[r.index]
        o.corner_reflectance = o.corner_emission = o.texture_pieces = None


def _material_index(me):
    mi = np.empty(len(me.polygons), np.int32)
    me.polygons.foreach_get("material_index", mi)
    n = max(len(me.materials), 1)
    return np.clip(mi, 0, n - 1)
