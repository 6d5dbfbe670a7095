"""Speed/accuracy trade-off of one example scene, inside Blender (started by run_tradeoff.py).

    blender -b --factory-startup SCENE.blend --python bench/tradeoff/tradeoff_scene.py -- \
        --zip build/radiosity.zip --ref REF.npz --out OUT.json [--ref-spp 16384]
        [--part-spp 4096] [--min-parts 2] [--cached-only] [--runs 3]
        [--presets DRAFT MEDIUM HIGH] [--eps 0.2 0.1 0.02 0.01] [--spp 16 64 256 1024]
        [--once-above 40]

1. The converged Cycles reference (bt_common.reference): REF.npz when it was made from the same
   .blend (sha256) and corners; extended with independent bakes (COMBINED to a corner colour
   attribute, non-adaptive, no denoising, 64 bounces, no clamping, seeds 1, 2, ..., --part-spp
   samples each) until it has --ref-spp samples in at least --min-parts parts, and saved there
   with its settings, its parts and their per-corner variance (the reference's own noise).
   --cached-only: the file as it is, never baked (a mismatch fails).
2. Round-robin over --runs repetitions: each configuration (our bake at each preset and at each
   CUSTOM epsilon, Cycles at each sample count) once per repetition, so slow phases of the shared
   machine hit all of them alike. A configuration whose first run took longer than --once-above
   seconds runs only once. Cycles runs use seeds 101, 102, ... (never the reference's seed 1:
   its first samples would repeat the reference's).
3. Errors against the reference (bench/corner_metric.py): every corner but emitters', the
   covered ones (the reference reads 0: under a box, on a contact) included; rRMSE (the main
   measure), NRMSE, the covered corners' share of the squared error, rRMSE over the uncovered
   corners only, and the figures with the reference's own noise removed in quadrature; per
   object (the scene's floor); the worst corners of the finest bake.
"""
import argparse
import json
import os
import statistics
import sys
import time

import bpy
import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import bt_common as bt  # noqa: E402


# corner_metric.corner_error's figures kept per point (medians over the runs).
MEASURES = ("rrmse", "nrmse", "mean_ratio", "rel_p50", "rel_p90", "covered_share",
            "covered_share_abs", "rrmse_uncovered", "nrmse_uncovered", "rrmse_covered",
            "ref_noise_rrmse", "ref_noise_nrmse", "ref_noise_rrmse_uncovered", "rrmse_denoised",
            "nrmse_denoised", "rrmse_uncovered_denoised")


def parse():
    p = argparse.ArgumentParser(prog="tradeoff_scene.py")
    p.add_argument("--zip", required=True)
    p.add_argument("--ref", required=True)
    p.add_argument("--out", required=True)
    p.add_argument("--ref-spp", type=int, default=16384)
    p.add_argument("--part-spp", type=int, default=4096)
    p.add_argument("--min-parts", type=int, default=2)
    p.add_argument("--cached-only", action="store_true",
                   help="use the cached reference as it is; fail when it does not match")
    p.add_argument("--runs", type=int, default=3)
    p.add_argument("--presets", nargs="*", default=["DRAFT", "MEDIUM", "HIGH"])
    p.add_argument("--eps", nargs="*", type=float, default=[0.2, 0.1, 0.02, 0.01])
    p.add_argument("--spp", nargs="*", type=int, default=[16, 64, 256, 1024])
    p.add_argument("--once-above", type=float, default=40.0)
    return p.parse_args(bt.args())


def per_object(x, r, emit, var, owner, objs):
    """Per object, with the scene's floor (so objects' squared errors add up to the scene's)."""
    out = {}
    floor = bt.cm.scene_floor(r, emit)
    for k, o in enumerate(objs):
        m = ~emit & (owner == k)
        if m.any():
            e = bt.errors(x, r, emit, var, mask=m, floor=floor)
            e["corners"] = int(m.sum())
            out[o.name] = e
    return out


def worst_corners(x, r, emit, owner, poly, pos, objs, n=8):
    rs = r.astype(np.float64)
    rel = np.abs(x - rs) / np.maximum(rs, bt.cm.scene_floor(r, emit))
    score = np.where(~emit, rel.max(axis=1), -1.0)
    idx = np.argsort(score)[::-1][:n]
    return [{"object": objs[owner[i]].name, "polygon": int(poly[i]),
             "position": [round(float(v), 3) for v in pos[i]],
             "ours": [round(float(v), 4) for v in x[i]], "ref": [round(float(v), 4) for v in r[i]],
             "rel_err": round(float(score[i]), 3)} for i in idx]


def main():
    a = parse()
    bt.install_addon(a.zip)
    scene = bpy.context.scene
    objs = bt.mesh_objects(scene)
    emit = bt.emitter_mask(objs)
    owner, poly = bt.corner_owner(objs)
    pos = bt.corner_positions(objs)
    ref, var, ref_meta = bt.reference(a.ref, scene, objs, a.ref_spp, a.part_spp, a.min_parts,
                                      make=not a.cached_only)
    covered = bt.cm.covered_mask(ref)
    judged = ~emit
    bt.log(f"{len(ref)} corners, {int(emit.sum())} emitter, {int((covered & judged).sum())} "
           f"covered (reference 0, judged too): {int(judged.sum())} judged; reference "
           f"{ref_meta['samples']} spp, its noise {ref_meta.get('noise')}")

    configs = [("ours", p, None) for p in a.presets]
    configs += [("ours", "CUSTOM", e) for e in a.eps]
    configs += [("cycles", s, None) for s in a.spp]
    runs = {i: [] for i in range(len(configs))}
    first_seconds = {}
    details = {}
    for rep in range(a.runs):
        for i, (kind, what, eps) in enumerate(configs):
            if rep > 0 and first_seconds[i] > a.once_above:
                continue
            if kind == "ours":
                st, sec = bt.our_bake(scene, what, eps, full=True)
                x = bt.all_corners(objs, bt.ATTR_OURS)
                rec = {"seconds": sec, "stats_seconds": st["seconds"]}
                if rep == 0:
                    details[i] = {"stats": {k: st.get(k) for k in (
                        "elements", "links", "cluster_links", "rays", "iterations", "refine_rounds",
                        "capped", "input_surfaces", "objects")},
                        "per_object": per_object(x, ref, emit, var, owner, objs),
                        "worst": worst_corners(x, ref, emit, owner, poly, pos, objs)}
            else:
                x, sec, _ = bt.cycles_bake(scene, objs, what, seed=101 + rep)
                rec = {"seconds": sec, "seed": 101 + rep}
                if rep == 0:
                    details[i] = {"per_object": per_object(x, ref, emit, var, owner, objs)}
            rec["cpu_seconds"] = bt.last_cpu
            rec.update(bt.errors(x, ref, emit, var))
            runs[i].append(rec)
            if rep == 0:
                first_seconds[i] = sec
            label = f"{what}" + (f" eps={eps}" if eps is not None else "") + \
                (" spp" if kind == "cycles" else "")
            bt.log(f"run {rep + 1}/{a.runs} {kind} {label}: {sec:.2f} s, "
                   + bt.cm.fmt_row(rec, ("rrmse", "rrmse_denoised", "rrmse_uncovered",
                                         "covered_share", "nrmse")))

    points = []
    for i, (kind, what, eps) in enumerate(configs):
        rs = runs[i]
        pt = {"kind": kind, "preset": what if kind == "ours" else None,
              "eps": eps, "spp": what if kind == "cycles" else None, "runs": len(rs),
              "seconds": statistics.median(r["seconds"] for r in rs),
              "seconds_all": [round(r["seconds"], 3) for r in rs],
              "cpu_seconds": statistics.median(r["cpu_seconds"] for r in rs),
              "rrmse_runs": [round(r["rrmse"], 5) for r in rs]}
        for k in MEASURES:
            if all(k in r for r in rs):
                pt[k] = statistics.median(r[k] for r in rs)
        pt.update(details.get(i, {}))
        points.append(pt)
    out = {"scene": os.path.splitext(os.path.basename(bpy.data.filepath))[0],
           "corners": int(len(ref)), "emitter_corners": int(emit.sum()),
           "covered_corners": int((covered & judged).sum()), "judged_corners": int(judged.sum()),
           "metric": "bench/corner_metric.py: every corner but emitters', covered included",
           "objects": [o.name for o in objs], "reference": ref_meta, "runs": a.runs,
           "once_above": a.once_above, "points": points,
           "date": time.strftime("%Y-%m-%d %H:%M"), "blender": bpy.app.version_string}
    with open(a.out, "w") as f:
        json.dump(out, f, indent=1)
    bt.result({"ok": True, "out": a.out})


main()
