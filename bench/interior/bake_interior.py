"""Bake one interior .blend through the add-on, inside Blender (started by run_interior.py).

    blender -b --factory-startup SCENE.blend --python bench/interior/bake_interior.py -- \
        --zip build/radiosity.zip --partial OUT.jsonl [--preset MEDIUM]
        [--compare-cycles --ref REF.npz --ref-spp 1024 --part-spp 512 --spp 16 64 256]

1. A full bake (bpy.ops.radiosity.bake(full=True)) at --preset.
2. The move stored in scene["radiosity_move"] (the armchair 0.5 m along +x, turned 0.6 rad about
   its vertical axis), then an incremental bake (full=False).
3. --compare-cycles (not "--cycles": bpy's Cycles add-on reads the command line and takes that
   for an abbreviation of its own options): the armchair back where it was; Cycles COMBINED
   bakes (glossy pass off: vertex colours hold no view-dependent light) to colour attributes
   at the same corners, at each --spp, against a reference of --ref-spp samples in independent
   parts cached at --ref (bench/tradeoff/bt_common.reference); our full bake's error and
   Cycles' by bench/corner_metric.py.

Each phase appends a JSON line to --partial as soon as it is known: a "started" line before a
bake, then its record (the operator's wall seconds, the process's CPU seconds, its peak
resident memory during the bake, everything in scene.radiosity.last_stats). A crash or a
timeout thus leaves what was measured and names the phase it stopped in.
"""
import argparse
import faulthandler
import json
import os
import resource
import sys
import time

import bpy

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import make_interior  # noqa: E402  (bench/interior: the evaluated triangle count)
import bt_common as bt  # noqa: E402  (bench/tradeoff, on PYTHONPATH: add-on, Cycles, errors)


def parse():
    p = argparse.ArgumentParser(prog="bake_interior.py")
    p.add_argument("--zip", required=True)
    p.add_argument("--partial", required=True)
    p.add_argument("--preset", default="MEDIUM")
    p.add_argument("--compare-cycles", action="store_true")
    p.add_argument("--ref")
    p.add_argument("--ref-spp", type=int, default=1024)
    p.add_argument("--part-spp", type=int, default=512)
    p.add_argument("--spp", nargs="*", type=int, default=[16, 64, 256])
    return p.parse_args(bt.args())


def emit(path, rec):
    with open(path, "a") as f:
        f.write(json.dumps(rec) + "\n")
    bt.log(json.dumps(rec)[:400])


def proc_status():
    """VmHWM and VmRSS of this process, kB."""
    out = {}
    with open("/proc/self/status") as f:
        for line in f:
            key = line.split(":")[0]
            if key in ("VmHWM", "VmRSS"):
                out[key.lower() + "_kb"] = int(line.split()[1])
    return out


def reset_peak():
    """Restarts VmHWM at the current RSS (Linux: clear_refs 5), so each bake reports its own
    peak; False where the kernel refuses."""
    try:
        with open("/proc/self/clear_refs", "w") as f:
            f.write("5")
        return True
    except OSError:
        return False


def native_phases():
    """Seconds and rays per solver phase of the last solve or update: the native stats' "phases"
    and "phase_rays", which last_stats leaves out (dicts); read from the add-on's kept solution
    (its internals, so None when they are not where this expects them)."""
    try:
        from radiosity.core import session
        kept = [x.kept for x in session.sessions().values() if x.kept is not None]
        stats = kept[-1].solver.stats()
        return {"seconds": dict(stats["phases"]), "rays": dict(stats["phase_rays"])}
    except Exception:       # noqa: BLE001 - an optional figure
        return None


def bake(a, scene, phase, full):
    emit(a.partial, {"phase": phase, "status": "started", "time": time.strftime("%H:%M:%S")})
    before = proc_status()
    own_peak = reset_peak()
    rec = {"phase": phase, "preset": a.preset, "rss_before_kb": before.get("vmrss_kb")}
    try:
        stats, seconds = bt.our_bake(scene, a.preset, full=full)
        rec.update(status="ok", seconds=seconds, cpu_seconds=bt.last_cpu, stats=stats,
                   phases=native_phases())
    except SystemExit as exc:           # the operator returned CANCELLED (an error report)
        rec.update(status="cancelled", error=str(exc))
    after = proc_status()
    rec.update(vmhwm_kb=after.get("vmhwm_kb"), vmrss_kb=after.get("vmrss_kb"),
               peak_is_this_bake=own_peak,
               ru_maxrss_kb=resource.getrusage(resource.RUSAGE_SELF).ru_maxrss)
    emit(a.partial, rec)
    return rec


def cycles_points(a, scene, ours):
    """Our full bake (corners `ours`) and Cycles at each --spp against the cached reference."""
    objs = bt.mesh_objects(scene)
    scene.render.bake.use_pass_glossy = False
    ref, var, meta = bt.reference(a.ref, scene, objs, a.ref_spp, a.part_spp, min_parts=2)
    mask = bt.emitter_mask(objs)
    points = [{"kind": "ours", "preset": a.preset, **ours["timing"],
               **bt.errors(ours["corners"], ref, mask, var)}]
    for k, spp in enumerate(a.spp):
        x, seconds, _ = bt.cycles_bake(scene, objs, spp, seed=101 + k)
        points.append({"kind": "cycles", "spp": spp, "seconds": seconds,
                       "cpu_seconds": bt.last_cpu, **bt.errors(x, ref, mask, var)})
        bt.log(f"Cycles {spp} spp: {seconds:.1f} s, rRMSE {points[-1]['rrmse']:.4f}")
    return {"phase": "cycles", "status": "ok", "points": points, "glossy_pass": False,
            "reference": {k: meta.get(k) for k in ("samples", "noise", "seconds")},
            "corners": int(len(ref)), "emitter_corners": int(mask.sum())}


def main():
    faulthandler.enable()           # a crash prints the Python stack it happened under
    a = parse()
    bt.install_addon(a.zip)
    scene = bpy.context.scene
    tris, meshes, instances = make_interior.count()
    emit(a.partial, {"phase": "scene", "status": "ok", "triangles": tris, "mesh_objects": meshes,
                     "instances": instances, "blend": os.path.basename(bpy.data.filepath),
                     "blender": bpy.app.version_string,
                     "interior": dict(scene.get("interior", {}))})
    full = bake(a, scene, "full", True)
    ours = None
    if a.compare_cycles and full["status"] == "ok":
        ours = {"corners": bt.all_corners(bt.mesh_objects(scene), bt.ATTR_OURS),
                "timing": {"seconds": full["seconds"], "cpu_seconds": full["cpu_seconds"]}}
    if "radiosity_move" not in scene:
        emit(a.partial, {"phase": "incremental", "status": "skipped",
                         "error": 'no scene["radiosity_move"]'})
    elif full["status"] == "ok":
        objs, ref = bt.move_targets(scene)
        start = bt.save_start(objs)
        bt.place(scene, objs, ref, start, 1.0)
        bake(a, scene, "incremental", False)
        if ours is not None:
            bt.place(scene, objs, ref, start, 0.0)
            emit(a.partial, cycles_points(a, scene, ours))
    bt.result({"ok": True})


if __name__ == "__main__":
    main()
