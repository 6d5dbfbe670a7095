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

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))  # bench/
import corner_metric as cm  # noqa: E402

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


# --- error measures: bench/corner_metric.py, the one definition ----------------------------

def errors(x, r, emit, ref_var=None, mask=None, floor=None):
    """corner_metric.corner_error: every corner but emitters' (covered ones included, their
    share of the error reported apart), rRMSE the headline, NRMSE, the reference's noise."""
    return cm.corner_error(x, r, emitter=emit, ref_var=ref_var, mask=mask, floor=floor)


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


def _zero_corner_colours(objs, names):
    """Sets the corner colour attributes `names` of objs' meshes to 0 (each mesh once, a byte
    colour through its sRGB bytes, which round-trip exactly); returns what they held, for
    _restore_corner_colours."""
    saved, seen = [], set()
    for o in objs:
        me = o.data
        if me.as_pointer() in seen:
            continue
        seen.add(me.as_pointer())
        for name in names:
            attr = me.color_attributes.get(name)
            if attr is None or attr.domain != "CORNER" or not len(attr.data):
                continue
            prop = "color_srgb" if attr.data_type == "BYTE_COLOR" else "color"
            values = np.empty(len(attr.data) * 4, dtype=np.float32)
            attr.data.foreach_get(prop, values)
            saved.append((me, name, prop, values))
            attr.data.foreach_set(prop, np.zeros_like(values))
        me.update()
    return saved


def _restore_corner_colours(saved):
    for me, name, prop, values in reversed(saved):
        me.color_attributes[name].data.foreach_set(prop, values)
        me.update()


def cycles_bake(scene, objs, samples, seed):
    """COMBINED bake of every object in objs to ATTR_CYCLES. Returns (corners (C,3), seconds).

    Bevel takes a new face's original index from a neighbour chosen by the corner data,
    colours included, so which evaluated corner Cycles bakes an original corner at follows the
    colour attributes' values. The target and our own output read as zero during the bake (a
    fresh target, as the add-on maps corners), whatever earlier bakes left in them."""
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
    _zero_corner_colours(objs, [ATTR_CYCLES])
    saved = _zero_corner_colours(objs, [ATTR_OURS, ATTR_OURS + "_sRGB"])
    global last_cpu
    c = time.process_time()
    t = time.perf_counter()
    try:
        res = bpy.ops.object.bake(type="COMBINED")
    finally:
        _restore_corner_colours(saved)
    seconds = time.perf_counter() - t
    last_cpu = time.process_time() - c
    if "FINISHED" not in res:
        raise SystemExit(f"Cycles bake failed: {res}")
    corners = all_corners(objs, ATTR_CYCLES)
    _zero_corner_colours(objs, [ATTR_CYCLES])   # our later bakes map corners with it at zero
    return corners, seconds, settings


def bsdf_sampling_only(scene, materials):
    """Cycles finds these materials' emission by BSDF sampling alone (no light sampling of them)
    and without the light threshold: another estimator of the same scene. Blender 3.4's light
    sampling reads a mesh lamp seen at grazing angles too dark (bench/results/reference_bias.md)."""
    for mat in materials:
        if hasattr(mat.cycles, "sample_as_light"):      # Blender 3.x
            mat.cycles.sample_as_light = False
        elif hasattr(mat.cycles, "emission_sampling"):  # 3.5 and later
            mat.cycles.emission_sampling = "NONE"
    scene.cycles.light_sampling_threshold = 0.0


def sha256(path):
    import hashlib
    h = hashlib.sha256()
    with open(path, "rb") as f:
        for chunk in iter(lambda: f.read(1 << 20), b""):
            h.update(chunk)
    return h.hexdigest()


def _load_parts(path, names, counts, blend_sha):
    """(parts list of (C,3) float32, part metas, meta) of a cached reference that matches this
    .blend's objects, corner counts and sha256; None otherwise. A reference saved before parts
    existed (one bake: `corners` + meta samples/seed) reads as one part."""
    if not os.path.exists(path):
        return None
    z = np.load(path, allow_pickle=False)
    meta = json.loads(str(z["meta"]))
    if not (meta["objects"] == names and meta["corners"] == counts
            and meta["blend_sha256"] == blend_sha):
        log(f"reference {path} does not match this .blend (sha {meta['blend_sha256'][:8]} vs "
            f"{blend_sha[:8]}, or its objects/corners): made anew")
        return None
    if "parts" in z.files:
        # Never mix Blender generations in one reference: 3.4's Cycles reads mesh lamps at
        # grazing angles too dark, 5.x does not (bench/results/reference_bias.md).
        ours = bpy.app.version[0]
        theirs = {str(p.get("blender", "?")).split(".")[0] for p in meta["parts"]}
        if theirs != {str(ours)}:
            raise SystemExit(f"reference {path} was made in Blender {sorted(theirs)}.x; this is "
                             f"{bpy.app.version_string}: use the reference made in this "
                             f"generation (bench/tradeoff/scenes.py ref()) or make one")
        return [p for p in z["parts"]], meta["parts"], meta
    one = {k: meta[k] for k in ("samples", "seed", "seconds") if k in meta}
    one.update(made=meta.get("made"), blender=meta.get("blender"))
    return [z["corners"]], [one], meta


def reference(path, scene, objs, want_spp, part_spp=4096, min_parts=2, make=True):
    """The cached Cycles reference at PATH, extended to at least want_spp samples in at least
    min_parts independent bakes (seeds 1, 2, ...: parts of part_spp samples) when make is true;
    saved after every part, so an interrupted run keeps what it baked.

    The file (np.savez_compressed): corners = the spp-weighted mean of the parts (float32 (C,3)),
    corners_var = the per-corner variance of that mean (corner_metric.combine_parts; absent with
    one part), parts (k,C,3), meta = JSON (settings, parts [{samples, seed, seconds, ...}],
    samples = their sum, objects, corners, blend sha256, the reference's own noise figures).
    Returns (corners float64, corners_var or None, meta)."""
    names = [o.name for o in objs]
    counts = [len(o.data.loops) for o in objs]
    blend_sha = sha256(bpy.data.filepath)
    got = _load_parts(path, names, counts, blend_sha)
    parts, pmeta, meta = got if got else ([], [], {})
    if not parts and not make:
        raise SystemExit(f"no matching reference at {path}")
    total = sum(p["samples"] for p in pmeta)
    if parts and total >= want_spp and len(parts) >= min_parts or parts and not make:
        log(f"reference {path}: cached, {total} spp in {len(parts)} part(s)")
    else:
        settings = {}
        while total < want_spp or len(parts) < min_parts:
            spp = min(part_spp, want_spp - total) if total < want_spp else part_spp
            seed = max([p.get("seed", 0) for p in pmeta] + [0]) + 1
            if seed > 100:
                raise SystemExit("reference seeds must stay below 101 (the trade-off's Cycles runs)")
            log(f"reference {path}: baking part {len(parts) + 1}, {spp} spp, seed {seed} ...")
            c = time.process_time()
            x, seconds, settings = cycles_bake(scene, objs, spp, seed)
            parts.append(x.astype(np.float32))
            pmeta.append({"samples": spp, "seed": seed, "seconds": round(seconds, 1),
                          "cpu_seconds": round(time.process_time() - c, 1),
                          "made": time.strftime("%Y-%m-%d %H:%M"), "blender": bpy.app.version_string,
                          "machine_load": [round(v, 2) for v in os.getloadavg()]})
            total += spp
            log(f"  part baked in {seconds:.0f} s; {total} spp so far")
            meta = _save_reference(path, parts, pmeta, settings or meta, objs, names, counts,
                                   blend_sha)
    mean, var = cm.combine_parts(np.stack(parts), [p["samples"] for p in pmeta])
    meta["cached"] = True
    return mean, var, meta


def _save_reference(path, parts, pmeta, settings, objs, names, counts, blend_sha):
    spp = [p["samples"] for p in pmeta]
    mean, var = cm.combine_parts(np.stack(parts), spp)
    emit = emitter_mask(objs)
    meta = {k: v for k, v in settings.items() if k not in ("samples", "seed", "parts", "noise")}
    meta.update(samples=int(sum(spp)), seed=[p["seed"] for p in pmeta], parts=pmeta,
                objects=names, corners=counts, blend=os.path.basename(bpy.data.filepath),
                blend_sha256=blend_sha, seconds=round(sum(p["seconds"] for p in pmeta), 1),
                made=pmeta[-1]["made"],
                bake="COMBINED to a FLOAT_COLOR CORNER attribute, all mesh objects selected; "
                     "the spp-weighted mean of independent bakes (seeds 1, 2, ...)",
                script="bench/tradeoff/bt_common.py reference()")
    if var is not None:
        e = cm.corner_error(mean, mean, emitter=emit, ref_var=var)
        meta["noise"] = {"rrmse": e["ref_noise_rrmse"], "nrmse": e["ref_noise_nrmse"],
                         "rrmse_uncovered": e["ref_noise_rrmse_uncovered"],
                         "how": "per-corner variance of the weighted mean of the parts "
                                "(corner_metric.combine_parts), judged corners, scene floor"}
    arrays = {"corners": mean.astype(np.float32), "parts": np.stack(parts).astype(np.float32),
              "meta": np.array(json.dumps(meta))}
    if var is not None:
        arrays["corners_var"] = var.astype(np.float32)
    os.makedirs(os.path.dirname(os.path.abspath(path)), exist_ok=True)
    tmp = path + ".tmp.npz"
    np.savez_compressed(tmp, **arrays)
    os.replace(tmp, path)
    return meta


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
