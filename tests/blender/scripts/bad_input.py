"""(d) Bad input, many cases in ONE Blender process (each start costs seconds).

Every case starts from an empty file (read_homefile: load_post drops the kept solutions, the
add-on stays enabled), builds its scene, bakes and reports. A failing bake must return
CANCELLED with an ERROR naming object and problem and leave the scene as it was: no colour
attribute written or changed anywhere and last_stats unchanged (`attempt()` records both).

RESULT: {case name: data}. Args: --cases a,b,... (default: all).
"""
import hashlib
import math
import os
import sys
import time
import traceback

import bpy
import numpy as np

import rt_common as rt
import scenes

rt.setup()
TMP = rt.arg("--tmp") or "/tmp"
INF = math.inf
NAN = math.nan


def fresh():
    """An empty file; the add-on stays enabled (re-enabled if this Blender disabled it)."""
    bpy.ops.wm.read_homefile(use_empty=True)
    if not hasattr(bpy.types.Scene, "radiosity"):
        rt.install_addon()


def props():
    return bpy.context.scene.radiosity


def mesh_objects():
    return [o for o in bpy.data.objects if o.type == "MESH"]


def colours():
    """{object name_full: (C,4) copy or None} for every mesh object (linked ones included)."""
    out = {}
    for o in mesh_objects():
        c = rt.corner_colors(o)
        out[o.name_full] = None if c is None else c.copy()
    return out


def _same(a, b):
    if a.keys() != b.keys():
        return False
    for k in a:
        if (a[k] is None) != (b[k] is None):
            return False
        if a[k] is not None and (a[k].shape != b[k].shape or not np.array_equal(a[k], b[k])):
            return False
    return True


def attempt(**kw):
    """Bake once; what a test needs to judge it (before/after comparison included)."""
    stats_before = props().last_stats
    before = colours()
    t0 = time.perf_counter()
    ok, err, reports = rt.bake(**kw)
    seconds = time.perf_counter() - t0
    after = colours()
    values, finite = {}, True
    for name, c in after.items():
        if c is not None:
            values[name] = [float(c[:, :3].min()), float(c[:, :3].max()),
                            bool((c[:, 3] == 1).all())]
            finite = finite and bool(np.isfinite(c).all())
    return {"ok": ok, "err": err, "reports": reports, "stats": rt.last_stats(),
            "stats_unchanged": props().last_stats == stats_before,
            "colours_unchanged": _same(before, after),
            "written": {n: c is not None for n, c in after.items()},
            "values": values, "finite": finite, "seconds": seconds}


def nrmse(a, b, names):
    x = np.concatenate([a[n][:, :3] for n in names])
    y = np.concatenate([b[n][:, :3] for n in names])
    return float(np.sqrt(np.mean((x - y) ** 2)) / max(np.sqrt(np.mean(y ** 2)), 1e-30))


def update():
    bpy.context.view_layer.update()


# --- basic bad input ----------------------------------------------------------------------------
def case_empty():
    return attempt()


def case_nan():
    scenes.build_diffuse_scene()
    verts, faces = rt.grid((0, 0, 1), (1, 0, 0), (0, 1, 0), 2)
    verts[4] = (NAN, 0.0, 1.0)
    rt.mesh_object("Broken", verts, faces)
    return attempt()


def case_zero_area():
    scenes.build_diffuse_scene()
    # two proper triangles and two degenerate ones (collinear / repeated vertex)
    verts = [(0, 0, 0.5), (1, 0, 0.5), (0, 1, 0.5), (2, 0, 0.5), (3, 0, 0.5), (4, 0, 0.5)]
    rt.mesh_object("Degenerate", verts, [(0, 1, 2), (3, 4, 5), (2, 1, 0)])
    return attempt()


def case_no_emitter():
    scenes.build_diffuse_scene()
    bpy.data.objects["Light"].hide_render = True
    return attempt()


def case_only_nonmesh():
    bpy.ops.mesh.primitive_plane_add()
    bpy.context.object.hide_render = True
    cu = bpy.data.curves.new("Text", "FONT")
    rt.link(bpy.data.objects.new("Text", cu))
    return attempt()


# --- extremes -----------------------------------------------------------------------------------
def case_inf_vertex():
    scenes.build_diffuse_scene()
    verts, faces = rt.grid((0, 0, 1), (1, 0, 0), (0, 1, 0), 2)
    obj = rt.mesh_object("Broken", verts, faces)
    obj.data.vertices[4].co = (INF, 0.0, 1.0)
    return {"stored": list(obj.data.vertices[4].co), "first": attempt()}


def case_matrix():
    """NaN/inf in matrix_world: at the first bake, and at a re-bake after a good one (colours
    and last_stats kept), through a parent, and in live mode."""
    scenes.build_diffuse_scene()
    box = bpy.data.objects["Box"]
    out = {}
    box.scale.x = NAN
    update()
    out["nan_scale_first"] = attempt()
    box.scale.x = 1.0
    update()
    out["good"] = attempt()
    box.location.x = INF        # Blender stores 3.4e38
    update()
    out["stored_location"] = list(box.location)
    out["inf_location_rebake"] = attempt()
    box.location.x = 0.0
    parent = rt.link(bpy.data.objects.new("Parent", None))
    box.parent = parent
    parent.rotation_euler.z = NAN
    update()
    out["nan_parent_rebake"] = attempt()
    box.parent = None
    update()
    out["restored"] = attempt()
    # Live: a NaN move queues a re-bake that fails without writing.
    errors = sys.modules[rt.ADDON].handlers.last_errors
    errors.clear()
    props().live = True
    before, stats_before = colours(), props().last_stats
    box.scale.z = NAN
    update()
    runs = sys.modules[rt.ADDON].pump(timeout=120)
    mod = sys.modules[rt.ADDON]
    live_state = mod.core.session.session(mod.bake.scene_key(bpy.context.scene)).live
    out["live"] = {"runs": runs, "errors": list(errors), "panel_failed": live_state.failed,
                   "colours_unchanged": _same(before, colours()),
                   "stats_unchanged": props().last_stats == stats_before}
    props().live = False
    box.scale.z = 1.0
    update()
    return out


def case_lights():
    scenes.build_diffuse_scene()
    lamp = rt.link(bpy.data.objects.new("Lamp", bpy.data.lights.new("Lamp", "POINT")))
    lamp.location = (0.0, 0.0, 1.5)
    out = {}
    lamp.data.energy = NAN
    out["nan_energy"] = attempt()
    lamp.data.energy = 100.0
    lamp.location.y = NAN
    update()
    out["nan_location"] = attempt()
    lamp.location.y = 0.0
    world = bpy.context.scene.world
    if world.node_tree is not None and world.node_tree.nodes.get("Background") is not None:
        world.node_tree.nodes["Background"].inputs["Strength"].default_value = NAN
    world.color = (NAN, 0.0, 0.0)
    update()
    out["nan_world"] = attempt()
    rt.black_world()
    lamp.data.energy = -100.0
    # An area light scaled to nothing: a singular matrix (no area, no light), not an error.
    panel = rt.link(bpy.data.objects.new("Panel", bpy.data.lights.new("Panel", "AREA")))
    panel.location = (0.0, 1.0, 1.5)
    panel.scale = (0.0, 0.0, 0.0)
    update()
    out["negative_energy"] = attempt()
    return out


def _emission_node(name):
    return bpy.data.materials[name].node_tree.nodes["Emission"]


def case_materials():
    """NaN/inf colours and strengths: refused naming object and material, first bake and
    re-bake; negative emission and reflectance above 1: clamped with a warning."""
    scenes.build_diffuse_scene()
    box_col = bpy.data.materials["Box"].node_tree.nodes["Diffuse BSDF"].inputs["Color"]
    emis = _emission_node("Light")
    out = {}
    box_col.default_value = (NAN, 0.3, 0.2, 1.0)
    out["nan_colour"] = attempt()
    box_col.default_value = (0.7, 0.35, 0.2, 1.0)
    emis.inputs["Strength"].default_value = NAN
    out["nan_strength"] = attempt()
    emis.inputs["Strength"].default_value = INF      # stored as 3.4e38
    out["stored_strength"] = emis.inputs["Strength"].default_value
    out["inf_strength"] = attempt()
    emis.inputs["Color"].default_value = (5.0, 5.0, 5.0, 1.0)   # x 3.4e38: past float range
    out["inf_colour_x_strength"] = attempt()
    emis.inputs["Color"].default_value = (1.0, 1.0, 1.0, 1.0)
    emis.inputs["Strength"].default_value = 10.0
    out["good"] = attempt()
    box_col.default_value = (0.7, NAN, 0.2, 1.0)
    out["nan_colour_rebake"] = attempt()
    # An infinite colour is stored as 3.4e38: a reflectance above 1, clamped with a warning.
    box_col.default_value = (0.7, INF, 0.2, 1.0)
    out["inf_colour"] = attempt()
    box_col.default_value = (0.7, 0.35, 0.2, 1.0)
    out["restored"] = attempt()
    return out


def case_clamps():
    """Negative emission -> 0 and reflectance >= 1 -> 0.999 (addon README "Materials"): the
    clamped input is the same input, so re-baking with the clamped value hits the kept
    solution."""
    scenes.build_diffuse_scene()
    v, f = rt.grid((-1.5, -1.5, 1.0), (0.5, 0, 0), (0, 0.5, 0), 1)
    rt.mesh_object("Dark", v, f, None, rt.emission_material("Negative", (1, 1, 1), -5.0))
    floor_col = bpy.data.materials["Floor"].node_tree.nodes["Diffuse BSDF"].inputs["Color"]
    floor_col.default_value = (5.0, 1.0, 0.5, 1.0)
    out = {"over": attempt()}
    _emission_node("Negative").inputs["Strength"].default_value = 0.0
    floor_col.default_value = (0.999, 0.999, 0.5, 1.0)
    out["clamped_by_hand"] = attempt()
    return out


def case_empty_meshes():
    scenes.build_diffuse_scene()
    rt.link(bpy.data.objects.new("Nothing", bpy.data.meshes.new("Nothing")))
    me = bpy.data.meshes.new("NoFaces")
    me.from_pydata([(0, 0, 1), (1, 0, 1), (0, 1, 1)], [(0, 1)], [])
    rt.link(bpy.data.objects.new("NoFaces", me))
    return attempt()


def case_huge_ngon():
    """One 100,000-corner polygon (a notched disc) lit by the scene's light. DRAFT keeps the suite
    short: the case is about finishing at all (MEDIUM took 70 s and reached the link cap, see
    the report of branch bad6)."""
    scenes.build_diffuse_scene()
    props().preset = "DRAFT"
    bpy.data.objects["Floor"].hide_render = True
    n = 100_000
    t = np.linspace(0.0, 2.0 * np.pi, n, endpoint=False)
    verts = np.stack([2.0 * np.cos(t), 2.0 * np.sin(t), np.zeros(n)], axis=1)
    # The last corner pulled in: the worst case of the native fan-apex search (it was O(n^2),
    # minutes at 100k corners; hierarchy.cpp split_polygon).
    verts[-1] = (1.8, 0.0, 0.0)
    rt.mesh_object("Disc", verts, [tuple(range(n))], None, bpy.data.materials["Floor"])
    r = attempt()
    r["disc_corners"] = len(bpy.data.objects["Disc"].data.loops)
    return r


def case_non_manifold():
    """Three fins on one edge, a loose edge and a loose vertex in the same mesh, and a face
    whose winding disagrees with its neighbour's."""
    scenes.build_diffuse_scene()
    verts = [(0, 0, 0.2), (0, 0, 1.0), (0.6, 0, 0.6), (-0.5, 0.4, 0.6), (-0.5, -0.4, 0.6),
             (1.5, 1.5, 0.5), (1.8, 1.5, 0.5), (1.0, 1.0, 1.0),
             (1.0, -1.0, 0.3), (1.5, -1.0, 0.3), (1.5, -0.5, 0.3), (1.0, -0.5, 0.3),
             (2.0, -1.0, 0.3), (2.0, -0.5, 0.3)]
    faces = [(0, 1, 2), (0, 1, 3), (1, 0, 4),            # edge 0-1 shared by three faces
             (8, 9, 10, 11), (9, 10, 13, 12)]            # the second one wound the other way
    me = bpy.data.meshes.new("NonManifold")
    me.from_pydata(verts, [(5, 6)], faces)               # 5-6 loose edge, 7 a loose vertex
    me.update()
    rt.link(bpy.data.objects.new("NonManifold", me))
    return attempt()


def case_modifiers_nothing():
    """Modifiers whose result has no faces: they take no part and cost nothing."""
    scenes.build_diffuse_scene()
    made = {}

    def plate(name, z):
        v, f = rt.grid((-0.5, -0.5, z), (1, 0, 0), (0, 1, 0), 3)
        return rt.mesh_object(name, v, f)

    masked = plate("Masked", 1.2)
    masked.vertex_groups.new(name="Nothing")      # a group with no vertex in it
    masked.modifiers.new("Mask", "MASK").vertex_group = "Nothing"
    welded = plate("Welded", 1.3)
    welded.modifiers.new("Weld", "WELD").merge_threshold = 100.0
    decimated = plate("Decimated", 1.4)
    decimated.modifiers.new("Decimate", "DECIMATE").ratio = 0.0
    cut = plate("Cut", 1.5)
    cv, cf = rt.box((0, 0, 1.5), (4, 4, 1))
    cutter = rt.mesh_object("Cutter", cv, cf)
    cutter.hide_render = True
    cutter.hide_set(True)
    boolean = cut.modifiers.new("Boolean", "BOOLEAN")
    boolean.operation, boolean.object = "DIFFERENCE", cutter
    update()
    dg = bpy.context.evaluated_depsgraph_get()
    for o in (masked, welded, decimated, cut):
        made[o.name] = len(o.evaluated_get(dg).data.polygons)
    r = attempt()
    r["evaluated_polygons"] = made
    return r


def _library(path):
    """A library .blend holding 'LibCrate' and an object 'Box' named like the local one."""
    objs = set()
    for name, centre in (("LibCrate", (-1.2, 1.0, 0.3)), ("Box", (1.2, -1.0, 0.3))):
        v, f = rt.box(centre, (0.5, 0.5, 0.6))
        me = bpy.data.meshes.new(name)
        me.from_pydata([tuple(map(float, x)) for x in v], [], f)
        objs.add(bpy.data.objects.new(name, me))
    bpy.data.libraries.write(path, objs, fake_user=True)
    for o in list(objs):
        me = o.data
        bpy.data.objects.remove(o)
        bpy.data.meshes.remove(me)


def case_linked_library():
    path = os.path.join(TMP, "bad_input_library.blend")
    _library(path)
    scenes.build_diffuse_scene()
    with bpy.data.libraries.load(path, link=True) as (src, dst):
        dst.objects = ["LibCrate", "Box"]
    for o in dst.objects:
        rt.link(o)
    update()
    out = {"linked": [o.name_full for o in dst.objects],
           "bake": attempt()}
    # Only linked meshes left (and the light): nothing can receive colours.
    for name in ("Floor", "Box", "Light"):
        o = bpy.data.objects.get((name, None))
        for coll in list(o.users_collection):
            coll.objects.unlink(o)
    update()
    out["only_linked"] = attempt()
    return out


def case_rename_delete():
    scenes.build_diffuse_scene()
    props().preset = "DRAFT"
    out = {"first": attempt()}
    names = lambda: [o.name for o in bpy.data.objects if o.type == "MESH"]  # noqa: E731

    def step(key):
        out[key] = attempt()
        inc = colours()
        out[key + "_full"] = attempt(full=True)
        full = colours()
        live = [n for n in names() if inc.get(n) is not None and full.get(n) is not None]
        out[key + "_nrmse"] = nrmse(inc, full, live)
        out[key + "_names"] = names()

    bpy.data.objects["Box"].name = "Crate"
    step("renamed")
    bpy.data.collections["Props"].name = "Stuff"
    step("collection_renamed")
    crate = bpy.data.objects["Crate"]
    me = crate.data
    bpy.data.objects.remove(crate)
    bpy.data.meshes.remove(me)
    step("deleted")
    # A new object under the deleted one's name, with another topology: no stale data.
    v, f = rt.grid((-1.2, 0.6, 0.4), (0.6, 0, 0), (0, 0.6, 0), 3)
    rt.mesh_object("Crate", v, f, None, bpy.data.materials["Box"])
    step("reused_name")
    c = rt.corner_colors(bpy.data.objects["Crate"])
    out["reused_corners"] = [len(bpy.data.objects["Crate"].data.loops),
                             None if c is None else len(c)]
    return out


def case_saved_blend():
    """Bake, save; open the file again in this process (load_post must drop the kept
    solution). The test opens the same file in a fresh Blender too (bad_input_reload.py)."""
    scenes.build_diffuse_scene()
    props().preset = "DRAFT"
    out = {"bake": attempt()}
    baked = colours()
    path = os.path.join(TMP, "bad_input_baked.blend")
    bpy.ops.wm.save_as_mainfile(filepath=path)
    bpy.ops.wm.open_mainfile(filepath=path)
    if not hasattr(bpy.types.Scene, "radiosity"):
        rt.install_addon()
    loaded = colours()
    out["path"] = path
    out["attribute_kept"] = _same(baked, loaded)
    out["stats_after_load"] = rt.last_stats()
    out["rebake"] = attempt()
    again = colours()
    out["rebake_nrmse"] = nrmse(again, baked, [n for n in baked if baked[n] is not None])
    return out


def case_rays():
    """An incremental bake reports the rays of that update, not the running total."""
    scenes.build_diffuse_scene()
    props().preset = "DRAFT"
    out = {"full": attempt()}
    bpy.data.objects["Box"].location.x += 0.3
    update()
    out["incremental"] = attempt()
    out["full_again"] = attempt(full=True)
    return out


CASES = {k[len("case_"):]: v for k, v in sorted(globals().items()) if k.startswith("case_")}
wanted = rt.arg("--cases")
wanted = wanted.split(",") if wanted else list(CASES)
results = {}
for name in wanted:
    fresh()
    try:
        results[name] = CASES[name]()
    except Exception:       # one broken case must not hide the others
        results[name] = {"crash": traceback.format_exc()}
    print(f"case {name} done", flush=True)
rt.result(**results)
