"""Our bake of a scenes_rendered scene against its stored converged Cycles bake.

Args: --scene NAME --ref PATH [--preset HIGH] [--gather-rays N] [--realize 1]. Errors as
bench/corner_metric.py (every compared corner; the emitter is not compared). Also reports what
the bake did to the scene: attributes of every mesh before/after (only the colour attribute may
be added), the stats' object and instance counts, the warnings.

--gather-rays N: the native final gather at every corner with N rays (Settings.gather_rays; off
in the shipped presets), which evaluates each corner at its own point and normal as Cycles does:
what is left is the add-on's share of the error (geometry, corner mapping), not the corner
output's. --realize 1: afterwards, every instance is made a real object (same mesh, same world
matrix; the instancers hidden from render) and the scene baked again: the instanced bake must
equal that one."""
import os
import sys

import bpy
import numpy as np

import rt_common as rt
import scenes_rendered

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "..", "bench"))
import corner_metric as cm  # noqa: E402


def attribute_names():
    return {me.name: sorted(a.name for a in me.attributes) for me in bpy.data.meshes}


def modifier_state():
    return {o.name: [(m.name, m.type) for m in o.modifiers] for o in bpy.data.objects}


which = rt.arg("--scene")
# "{v}" in the path: the reference made by this Blender generation ("v3": 3.x, "v5": 4.x and
# later). Cycles bakes the corner its first matching evaluated triangle holds, and Bevel
# orders its faces differently in 3.4 and 5.x: the same scene bakes differently there.
ref_path = rt.arg("--ref").replace("{v}", "v3" if bpy.app.version < (4, 0, 0) else "v5")
rt.setup()
gather_rays = int(rt.arg("--gather-rays", "0"))
if gather_rays:
    import radiosity.core.presets as presets
    _make = presets.make_settings

    def make_settings(*a, **k):
        settings = _make(*a, **k)
        settings.gather_rays = gather_rays
        return settings
    presets.make_settings = make_settings
names, emitter = scenes_rendered.BUILDERS[which]()
bpy.context.scene.radiosity.preset = rt.arg("--preset", "HIGH")
before_attrs, before_mods = attribute_names(), modifier_state()
before_objects = sorted(o.name for o in bpy.data.objects)
ok, err, reports = rt.bake()
out = {"ok": ok, "err": err, "reports": reports, "stats": rt.last_stats(),
       "fake": rt.native_is_fake(), "names": names}
after_attrs = attribute_names()
out["added_attributes"] = {n: sorted(set(after_attrs[n]) - set(before_attrs.get(n, [])))
                           for n in after_attrs}
out["removed_attributes"] = {n: sorted(set(before_attrs[n]) - set(after_attrs.get(n, [])))
                             for n in before_attrs}
out["modifiers_unchanged"] = modifier_state() == before_mods
out["objects_unchanged"] = sorted(o.name for o in bpy.data.objects) == before_objects
if ok:
    objs = [bpy.data.objects[n] for n in names]
    cols = [rt.corner_colors(o) for o in objs]
    out["written"] = [c is not None for c in cols]
    if all(c is not None for c in cols):
        ours = np.concatenate([c[:, :3] for c in cols])
        if rt.arg("--dump", None):      # corners and their positions, to study them (not the tests)
            pos = np.concatenate([np.array([tuple(o.matrix_world @ o.data.vertices[lp.vertex_index].co)
                                            for lp in o.data.loops]) for o in objs])
            np.savez(rt.arg("--dump"), ours=ours, pos=pos)
        ref = np.load(ref_path)
        out["shape_ok"] = ours.shape == ref.shape
        if out["shape_ok"]:
            out["all"] = cm.corner_error(ours, ref)
            floor = cm.scene_floor(ref)
            out["per_object"] = {}
            start = 0
            for o, c in zip(objs, cols):
                n = len(c)
                m = np.zeros(len(ref), bool)
                m[start:start + n] = True
                e = cm.corner_error(ours, ref, mask=m, floor=floor)
                out["per_object"][o.name] = {
                    **{k: e[k] for k in ("rrmse", "nrmse", "covered") if k in e},
                    "ours_mean": ours[start:start + n].mean(axis=0).tolist(),
                    "ref_mean": ref[start:start + n].mean(axis=0).tolist()}
                start += n


def realize_instances():
    """Every instance as a real object (its evaluated mesh, its world matrix); the instancers
    hidden from render. Returns how many were made."""
    dg = bpy.context.evaluated_depsgraph_get()
    made, instancers = [], set()
    for inst in dg.object_instances:
        if not inst.is_instance or inst.object.type != "MESH":
            continue
        me = bpy.data.meshes.new_from_object(inst.object)
        made.append((me, [m for m in inst.object.data.materials],
                     [list(r) for r in inst.matrix_world]))
        instancers.add(inst.parent.original.name)
    for i, (me, mats, m) in enumerate(made):
        me.materials.clear()
        for mat in mats:
            me.materials.append(mat)
        obj = rt.link(bpy.data.objects.new(f"Real{i}", me))
        from mathutils import Matrix
        obj.matrix_world = Matrix(m)
    for name in instancers:
        bpy.data.objects[name].hide_render = True
    return len(made)


if ok and rt.arg("--realize", "0") == "1":
    instanced = np.concatenate([rt.corner_colors(bpy.data.objects[n])[:, :3] for n in names])
    out["realized"] = realize_instances()
    ok2, err2, reports2 = rt.bake(full=True)
    out["realized_ok"] = ok2
    if ok2:
        st2 = rt.last_stats()
        out["realized_stats"] = {k: st2.get(k) for k in ("objects", "scene_objects", "instances")}
        real = np.concatenate([rt.corner_colors(bpy.data.objects[n])[:, :3] for n in names])
        out["instanced_vs_realized"] = cm.corner_error(instanced, real)
        out["realized_vs_cycles"] = cm.corner_error(real, np.load(ref_path))
rt.result(**out)
