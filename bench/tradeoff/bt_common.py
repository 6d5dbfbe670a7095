"""Helpers for the benchmark scripts that run inside Blender (bench/tradeoff/*_scene.py).

Imported from a script started as `blender -b FILE.blend --python SCRIPT -- ARGS` with this
directory on PYTHONPATH (bench/tradeoff/bt_run.py arranges that). No add-on code is copied here:
the add-on is installed from the zip and its own modules are imported where needed.
"""
import json
import math
import os
import sys
import time

import bpy
import numpy as np

ATTR_OURS = "Radiosity"
ATTR_CYCLES = "CyclesBake"
# Process CPU seconds (all threads) of the last cycles_bake / our_bake: a load-robust companion
# to wall time on a shared machine (both renderers run their threads inside this process).
last_cpu = float("nan")


def args():
    argv = sys.argv
    return argv[argv.index("--") + 1:] if "--" in argv else []


def install_addon(zip_path):
    bpy.ops.preferences.addon_install(filepath=os.path.abspath(zip_path), overwrite=True)
    bpy.ops.preferences.addon_enable(module="radiosity")
    if not hasattr(bpy.ops.radiosity, "bake"):
        raise SystemExit("the radiosity add-on did not register")
    import radiosity  # noqa: F401
    return sys.modules["radiosity"]


def result(data):
    print("RESULT " + json.dumps(data), flush=True)


def log(msg):
    print(f"[bench {time.strftime('%H:%M:%S')}] {msg}", flush=True)


# --- corners -----------------------------------------------------------------------------

def mesh_objects(scene):
    """Every renderable mesh object, sorted by name: the fixed corner order of all arrays."""
    return sorted((o for o in scene.objects if o.type == "MESH" and not o.hide_render),
                  key=lambda o: o.name)


def corner_colors(obj, name):
    me = obj.data
    attr = me.color_attributes[name]
    buf = np.empty(len(me.loops) * 4, dtype=np.float32)
    attr.data.foreach_get("color", buf)
    return buf.reshape(-1, 4)[:, :3].copy()


def all_corners(objs, name):
    return np.concatenate([corner_colors(o, name) for o in objs])


def emitter_mask(objs):
    """True for corners of polygons whose material emits (the add-on's own material reading)."""
    from radiosity import materials
    parts = []
    for o in objs:
        me = o.data
        emits = []
        for slot in o.material_slots:
            _, e, _ = materials.material_values(slot.material)
            emits.append(bool(np.max(e) > 0))
        if not emits:
            emits = [False]
        mi = np.empty(len(me.polygons), dtype=np.int32)
        me.polygons.foreach_get("material_index", mi)
        tot = np.empty(len(me.polygons), dtype=np.int32)
        me.polygons.foreach_get("loop_total", tot)
        poly_emit = np.array(emits)[np.clip(mi, 0, len(emits) - 1)]
        parts.append(np.repeat(poly_emit, tot))
    return np.concatenate(parts)


def corner_owner(objs):
    """(object index per corner, polygon index per corner)."""
    oi, pi = [], []
    for k, o in enumerate(objs):
        me = o.data
        tot = np.empty(len(me.polygons), dtype=np.int32)
        me.polygons.foreach_get("loop_total", tot)
        oi.append(np.full(len(me.loops), k, np.int32))
        pi.append(np.repeat(np.arange(len(me.polygons), dtype=np.int32), tot))
    return np.concatenate(oi), np.concatenate(pi)


def corner_positions(objs):
    out = []
    for o in objs:
        me = o.data
        co = np.empty(len(me.vertices) * 3, np.float64)
        me.vertices.foreach_get("co", co)
        co = co.reshape(-1, 3)
        vi = np.empty(len(me.loops), np.int32)
        me.loops.foreach_get("vertex_index", vi)
        m = np.array(o.matrix_world)
        p = co[vi] @ m[:3, :3].T + m[:3, 3]
        out.append(p)
    return np.concatenate(out)


# --- error measures (shared/NOTES.md) --------------------------------------------------------

def errors(x, r, keep):
    """rRMSE and NRMSE of x against reference r over the corners `keep` (bool), all channels.

    rRMSE = sqrt(mean(((x - r) / max(r, 0.05 mean r))^2)); NRMSE = RMS(x - r) / RMS(r)."""
    xs, rs = x[keep].astype(np.float64), r[keep].astype(np.float64)
    floor = 0.05 * rs.mean()
    rel = (xs - rs) / np.maximum(rs, floor)
    return {"rrmse": float(np.sqrt(np.mean(rel ** 2))),
            "nrmse": float(np.sqrt(np.mean((xs - rs) ** 2)) / np.sqrt(np.mean(rs ** 2))),
            "mean_ratio": float(xs.mean() / rs.mean()),
            "rel_p50": float(np.percentile(np.abs(rel), 50)),
            "rel_p90": float(np.percentile(np.abs(rel), 90))}


# --- Cycles ----------------------------------------------------------------------------------

def cycles_setup(scene, samples, seed, bounces=64):
    scene.render.engine = "CYCLES"
    c = scene.cycles
    c.device = "CPU"
    c.samples = samples
    c.use_adaptive_sampling = False
    c.use_denoising = False
    c.max_bounces = c.diffuse_bounces = bounces
    c.glossy_bounces = c.transmission_bounces = c.volume_bounces = bounces
    c.transparent_max_bounces = bounces
    c.sample_clamp_direct = c.sample_clamp_indirect = 0.0
    c.caustics_reflective = c.caustics_refractive = True
    c.seed = seed
    c.use_animated_seed = False
    scene.render.bake.target = "VERTEX_COLORS"
    scene.render.bake.use_clear = True
    return {"samples": samples, "seed": seed, "adaptive": False, "denoise": False,
            "max_bounces": bounces, "diffuse_bounces": bounces, "clamp": 0.0,
            "device": "CPU", "threads": scene.render.threads if scene.render.threads_mode == "FIXED"
            else "auto", "blender": bpy.app.version_string}


def cycles_bake(scene, objs, samples, seed):
    """COMBINED bake of every object in objs to ATTR_CYCLES. Returns (corners (C,3), seconds)."""
    settings = cycles_setup(scene, samples, seed)
    for o in scene.objects:
        o.select_set(False)
    for o in objs:
        me = o.data
        attr = me.color_attributes.get(ATTR_CYCLES)
        if attr is None:
            attr = me.color_attributes.new(ATTR_CYCLES, "FLOAT_COLOR", "CORNER")
        me.color_attributes.active_color = attr
        o.select_set(True)
    bpy.context.view_layer.objects.active = objs[0]
    global last_cpu
    c = time.process_time()
    t = time.perf_counter()
    res = bpy.ops.object.bake(type="COMBINED")
    seconds = time.perf_counter() - t
    last_cpu = time.process_time() - c
    if "FINISHED" not in res:
        raise SystemExit(f"Cycles bake failed: {res}")
    return all_corners(objs, ATTR_CYCLES), seconds, settings


# --- our bake --------------------------------------------------------------------------------

def our_bake(scene, preset, eps=None, full=True):
    """bpy.ops.radiosity.bake; returns (last_stats dict, wall seconds of the operator call)."""
    props = scene.radiosity
    props.preset = preset
    if eps is not None:
        props.error_threshold = eps
    global last_cpu
    c = time.process_time()
    t = time.perf_counter()
    res = bpy.ops.radiosity.bake(full=full)
    seconds = time.perf_counter() - t
    last_cpu = time.process_time() - c
    if "FINISHED" not in res:
        raise SystemExit(f"radiosity bake failed: {res}")
    return json.loads(props.last_stats), seconds


# --- moves -----------------------------------------------------------------------------------

def move_targets(scene):
    mv = scene["radiosity_move"]
    name = mv["object"]
    if name in bpy.data.objects:
        return [bpy.data.objects[name]], bpy.data.objects[name]
    objs = [o for o in bpy.data.collections[name].all_objects if o.parent is None]
    return objs, objs[0]


def place(scene, objs, ref, start, frac):
    """Put the moved object(s) at fraction `frac` of the stored move (0 = start, 1 = target).

    start: {object name: (location, rotation_z)} saved before any move."""
    mv = scene["radiosity_move"]
    loc0 = np.array(start[ref.name][0])
    target = np.array(mv["location"], dtype=float)
    delta = (target - loc0) * frac
    angle = math.radians(float(mv.get("rotation_z_deg", 0.0))) * frac
    for o in objs:
        o.location = tuple(np.array(start[o.name][0]) + delta)
        o.rotation_euler.z = start[o.name][1] + angle
    bpy.context.view_layer.update()


def save_start(objs):
    return {o.name: (tuple(o.location), o.rotation_euler.z) for o in objs}
