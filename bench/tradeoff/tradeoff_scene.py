"""Speed/accuracy trade-off of one example scene, inside Blender (started by run_tradeoff.py).

    blender -b --factory-startup SCENE.blend --python bench/tradeoff/tradeoff_scene.py -- \
        --zip build/radiosity.zip --ref REF.npz --out OUT.json [--ref-spp 4096] [--runs 3]
        [--presets DRAFT MEDIUM HIGH] [--eps 0.2 0.1 0.02 0.01] [--spp 16 64 256 1024]
        [--once-above 40]

1. The converged Cycles reference: loaded from REF.npz when it exists and was made from the same
   .blend (sha256), the same corners and at least --ref-spp samples; otherwise baked (COMBINED to
   a corner colour attribute, non-adaptive, no denoising, 64 bounces, no clamping, seed 1) and
   saved there, with its settings, compressed.
2. Round-robin over --runs repetitions: each configuration (our bake at each preset and at each
   CUSTOM epsilon, Cycles at each sample count) once per repetition, so slow phases of the shared
   machine hit all of them alike. A configuration whose first run took longer than --once-above
   seconds runs only once. Cycles runs use seeds 101, 102, ... (never the reference's seed 1:
   its first samples would repeat the reference's).
3. Errors against the reference over every corner but emitters' and those the reference has
   exactly 0 (covered: under a box, inside a contact); rRMSE (the main measure) and NRMSE as in
   shared/NOTES.md; per object; the worst corners of the finest bake.
"""
import argparse
import hashlib
import json
import os
import statistics
import sys
import time

import bpy
import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import bt_common as bt  # noqa: E402


def parse():
    p = argparse.ArgumentParser(prog="tradeoff_scene.py")
    p.add_argument("--zip", required=True)
    p.add_argument("--ref", required=True)
    p.add_argument("--out", required=True)
    p.add_argument("--ref-spp", type=int, default=4096)
    p.add_argument("--runs", type=int, default=3)
    p.add_argument("--presets", nargs="*", default=["DRAFT", "MEDIUM", "HIGH"])
    p.add_argument("--eps", nargs="*", type=float, default=[0.2, 0.1, 0.02, 0.01])
    p.add_argument("--spp", nargs="*", type=int, default=[16, 64, 256, 1024])
    p.add_argument("--once-above", type=float, default=40.0)
    return p.parse_args(bt.args())


def sha256(path):
    h = hashlib.sha256()
    with open(path, "rb") as f:
        for chunk in iter(lambda: f.read(1 << 20), b""):
            h.update(chunk)
    return h.hexdigest()


def load_or_make_reference(a, scene, objs):
    names = [o.name for o in objs]
    counts = [len(o.data.loops) for o in objs]
    blend_sha = sha256(bpy.data.filepath)
    if os.path.exists(a.ref):
        z = np.load(a.ref, allow_pickle=False)
        meta = json.loads(str(z["meta"]))
        if (meta["objects"] == names and meta["corners"] == counts
                and meta["blend_sha256"] == blend_sha and meta["samples"] >= a.ref_spp):
            bt.log(f"reference {a.ref}: cached, {meta['samples']} spp")
            meta["cached"] = True
            return z["corners"].astype(np.float32), meta
        bt.log(f"reference {a.ref} does not match (samples {meta['samples']}, sha "
               f"{meta['blend_sha256'][:8]} vs {blend_sha[:8]}): re-baking")
    bt.log(f"baking the Cycles reference at {a.ref_spp} spp ...")
    ref, seconds, settings = bt.cycles_bake(scene, objs, a.ref_spp, seed=1)
    meta = dict(settings, objects=names, corners=counts, blend=os.path.basename(bpy.data.filepath),
                blend_sha256=blend_sha, seconds=seconds, made=time.strftime("%Y-%m-%d %H:%M"),
                bake="COMBINED to a FLOAT_COLOR CORNER attribute, all mesh objects selected",
                script="bench/tradeoff/tradeoff_scene.py")
    os.makedirs(os.path.dirname(os.path.abspath(a.ref)), exist_ok=True)
    np.savez_compressed(a.ref, corners=ref.astype(np.float32), meta=np.array(json.dumps(meta)))
    bt.log(f"reference baked in {seconds:.1f} s, saved to {a.ref}")
    meta["cached"] = False
    return ref, meta


def per_object(x, r, keep, owner, objs):
    out = {}
    for k, o in enumerate(objs):
        m = keep & (owner == k)
        if m.any():
            e = bt.errors(x, r, m)
            e["corners"] = int(m.sum())
            out[o.name] = e
    return out


def worst_corners(x, r, keep, owner, poly, pos, objs, n=8):
    rs = r.astype(np.float64)
    floor = 0.05 * rs[keep].mean()
    rel = np.abs(x - rs) / np.maximum(rs, floor)
    score = np.where(keep, rel.max(axis=1), -1.0)
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
    ref, ref_meta = load_or_make_reference(a, scene, objs)
    covered = ~(ref > 0).any(axis=1)
    keep = ~emit & ~covered
    bt.log(f"{len(ref)} corners, {int(emit.sum())} emitter, {int((covered & ~emit).sum())} "
           f"covered (reference 0): {int(keep.sum())} judged")

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
                        "per_object": per_object(x, ref, keep, owner, objs),
                        "worst": worst_corners(x, ref, keep, owner, poly, pos, objs)}
            else:
                x, sec, _ = bt.cycles_bake(scene, objs, what, seed=101 + rep)
                rec = {"seconds": sec, "seed": 101 + rep}
                if rep == 0:
                    details[i] = {"per_object": per_object(x, ref, keep, owner, objs)}
            rec["cpu_seconds"] = bt.last_cpu
            rec.update(bt.errors(x, ref, keep))
            rec["all_nonemitter"] = bt.errors(x, ref, ~emit)
            runs[i].append(rec)
            if rep == 0:
                first_seconds[i] = sec
            label = f"{what}" + (f" eps={eps}" if eps is not None else "") + \
                (" spp" if kind == "cycles" else "")
            bt.log(f"run {rep + 1}/{a.runs} {kind} {label}: {sec:.2f} s, rRMSE "
                   f"{rec['rrmse']:.4f}, NRMSE {rec['nrmse']:.4f}")

    points = []
    for i, (kind, what, eps) in enumerate(configs):
        rs = runs[i]
        pt = {"kind": kind, "preset": what if kind == "ours" else None,
              "eps": eps, "spp": what if kind == "cycles" else None, "runs": len(rs),
              "seconds": statistics.median(r["seconds"] for r in rs),
              "seconds_all": [round(r["seconds"], 3) for r in rs],
              "cpu_seconds": statistics.median(r["cpu_seconds"] for r in rs),
              "rrmse": statistics.median(r["rrmse"] for r in rs),
              "nrmse": statistics.median(r["nrmse"] for r in rs),
              "mean_ratio": statistics.median(r["mean_ratio"] for r in rs),
              "rel_p50": statistics.median(r["rel_p50"] for r in rs),
              "rel_p90": statistics.median(r["rel_p90"] for r in rs),
              "rrmse_all": [round(r["rrmse"], 5) for r in rs],
              "rrmse_incl_covered": statistics.median(r["all_nonemitter"]["rrmse"] for r in rs),
              "nrmse_incl_covered": statistics.median(r["all_nonemitter"]["nrmse"] for r in rs)}
        pt.update(details.get(i, {}))
        points.append(pt)
    out = {"scene": os.path.splitext(os.path.basename(bpy.data.filepath))[0],
           "corners": int(len(ref)), "emitter_corners": int(emit.sum()),
           "covered_corners": int((covered & ~emit).sum()), "judged_corners": int(keep.sum()),
           "objects": [o.name for o in objs], "reference": ref_meta, "runs": a.runs,
           "once_above": a.once_above, "points": points,
           "date": time.strftime("%Y-%m-%d %H:%M"), "blender": bpy.app.version_string}
    with open(a.out, "w") as f:
        json.dump(out, f, indent=1)
    bt.result({"ok": True, "out": a.out})


main()
