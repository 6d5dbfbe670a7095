"""Accuracy of native full solves against the cached Cycles references, without Blender's bake.

A quick check for solver changes: each scene, exported as the add-on gathers it
(bench/export_scene.py, in Blender, into a temporary .npz unless a .npz is given), is built with
the add-on's own core (core.scene_data.build_native_scene: objects, area lights, lights, world)
and solved through the native module at each preset, then judged against
bench/tradeoff/refs/SCENE_cycles5.npz (Blender 5.x; --reference binary: SCENE_cycles.npz, made
in Blender 3.4, whose Cycles reads mesh lamps at grazing angles too dark) with
bench/corner_metric.py, the one definition of the
error: every corner but emitters', covered corners (the reference reads 0: under a box, on a
contact) included, rRMSE = sqrt(mean(((x-r)/max(r, 0.05 mean r))^2)) the headline, NRMSE, the
covered corners' share of the squared error, rRMSE over uncovered corners only, and, when the
reference stores its own noise (several independent Cycles bakes), the error with that noise
removed in quadrature. Per surface (each written object) it prints the mean ours / reference,
so that a bias shows where it is; with two or more --seeds it splits the error into the
solver's own noise (from the seeds' differences) and its bias (the seeds' mean against the
reference, both noises removed): a bias that more rays cannot take away.

    python3 bench/accuracy_native.py [--native-dir DIR] [--presets DRAFT,MEDIUM] [--seeds 1,2,3]
                                     [--set rays_per_link=64 ...] [--md OUT.md] [--save DIR]
                                     [--reference bpy|binary]
                                     [SCENE ...]

SCENE: a scene name (default: all of bench/tradeoff/scenes.py: cornell_box, box_room,
chair_room, full_room, lights_room) or an exported SCENE.npz (its reference is
refs/SCENE_cycles5.npz). Objects are matched to the reference's by name (the references store
them sorted by name). --native-dir picks another build (e.g. a worktree at the commit before a
change) to compare two builds on the same scenes. --md writes the table, with the command, the
commit and the references' samples and noise, to a markdown file.
"""
import argparse
import json
import os
import subprocess
import sys
import tempfile
import time

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
sys.path.insert(0, HERE)
sys.path.insert(0, os.path.join(HERE, "tradeoff"))
sys.path.insert(0, os.path.join(ROOT, "addon"))
import corner_metric as cm  # noqa: E402
import scenes as bt_scenes  # noqa: E402


def export(name, tmp):
    """example .blend -> .npz through bench/export_scene.py in Debian's Blender."""
    import bt_run
    out = os.path.join(tmp, f"{name}.npz")
    env = dict(os.environ, PATH=bt_run.path_without_pyenv(os.environ.get("PATH", "")),
               PYTHONDONTWRITEBYTECODE="1")
    cmd = [bt_run.blender_exe(), "-b", "--factory-startup", bt_scenes.blend(name),
           "--python-exit-code", "1", "--python", os.path.join(HERE, "export_scene.py"), "--", out]
    proc = subprocess.run(cmd, env=env, capture_output=True, text=True)
    if proc.returncode != 0 or not os.path.exists(out):
        raise SystemExit(f"exporting {name} failed (exit {proc.returncode}):\n"
                         + (proc.stdout + proc.stderr)[-3000:])
    return out


def scene_input(z):
    """The exported arrays as the add-on's core.SceneInput."""
    from radiosity.core import lights as core_lights
    from radiosity.core import scene_data
    si = scene_data.SceneInput()
    for c in z["clusters"]:
        name, parent = str(c).split("\t")
        si.add_cluster(name, int(parent))
    written = []
    for i, o in enumerate(z["objects"]):
        name, cl = str(o).split("\t")
        g = lambda k, d=None: z[f"o{i}_{k}"] if f"o{i}_{k}" in z.files else d  # noqa: E731
        si.objects.append(scene_data.ObjectInput(
            name=name, cluster=int(cl), vertices=g("vertices"), loop_starts=g("loop_starts"),
            loop_totals=g("loop_totals"), corner_verts=g("corner_verts"),
            reflectance=g("reflectance"), emission=g("emission"), corner_perm=g("corner_perm"),
            two_sided=g("two_sided"), occluder=bool(g("occluder", True)), output=bool(g("output", True)),
            corner_map=g("corner_map")))
        written.append(bool(g("written", True)))
    if "lights" in z.files:
        for li in json.loads(str(z["lights"])):
            li["intensity"] = tuple(li["intensity"])
            si.lights.append(core_lights.LightInput(**li))
    return si, written


def apply_settings(st, assignments):
    """NAME=VALUE strings into the Settings st, each value as the field's type."""
    for kv in assignments:
        k, v = kv.split("=", 1)
        t = type(getattr(st, k))
        setattr(st, k, v.lower() in ("1", "true", "yes", "on") if t is bool else t(v))


def git_commit():
    """HEAD, and the commit of the solver and add-on measured (bench/tradeoff/bt_run.py)."""
    import bt_run
    return bt_run.git_commit()


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--native-dir", default=os.path.join(ROOT, "build", "native"))
    ap.add_argument("--presets", default="DRAFT,MEDIUM")
    ap.add_argument("--seeds", default="", help="comma-separated Settings.seed values (default: the preset's)")
    ap.add_argument("--set", action="append", default=[], metavar="NAME=VALUE",
                    help="override a Settings field, e.g. --set rays_per_link=64 (repeatable)")
    ap.add_argument("--md", help="also write the table to this markdown file")
    ap.add_argument("--save", metavar="DIR", help="also save each solve's corners (float32, the "
                    "reference's order) as DIR/SCENE_PRESET.npz, to judge them again later")
    ap.add_argument("--phases", action="store_true",
                    help="also print each solve's wall time and rays per phase")
    ap.add_argument("--reference", choices=("bpy", "binary"), default="bpy",
                    help="judge against the references made in bpy 5.x (default) or Blender 3.4")
    ap.add_argument("--ref", help="the Cycles reference (.npz) of a single exported scene given as "
                    "F.npz (e.g. an interior's, as bench/interior/run_interior.py --cycles caches it)")
    ap.add_argument("scenes", nargs="*")
    a = ap.parse_args()
    sys.path.insert(0, a.native_dir)
    import radiosity_native as rn
    from radiosity.core import scene_data
    print("module:", rn.__file__, flush=True)
    tmp = tempfile.mkdtemp(prefix="accuracy-native-")
    rows, refs = [], {}
    for arg in a.scenes or bt_scenes.SCENES:
        if arg.endswith(".npz"):
            path, name = arg, os.path.splitext(os.path.basename(arg))[0]
        else:
            name, path = arg, export(arg, tmp)
        z = np.load(path)
        ref, ref_var, meta = cm.load_reference(a.ref or bt_scenes.ref(name, a.reference))
        si, written = scene_input(z)
        ids = [i for i, o in enumerate(si.objects) if written[i]]
        order = sorted(ids, key=lambda i: si.objects[i].name)
        if [si.objects[i].name for i in order] != meta["objects"]:
            raise SystemExit(f"{name}: objects {[si.objects[i].name for i in order]} differ from "
                             f"the reference's {meta['objects']}")
        emit = np.concatenate([si.objects[i].written_values(np.repeat(
            np.any(si.objects[i].emission > 0, axis=1), si.objects[i].loop_totals)) for i in order])
        refs[name] = (meta, cm.corner_error(ref, ref, emitter=emit, ref_var=ref_var))
        counts = [si.objects[i].written_corner_count for i in order]
        by_preset = {}
        for preset, seed in [(p, sd) for p in a.presets.split(",")
                             for sd in (a.seeds.split(",") if a.seeds else [None])]:
            st = rn.Settings.preset(preset)
            if seed is not None:
                st.seed = int(seed)
            apply_settings(st, a.set)
            scene, _, oids = scene_data.build_native_scene(rn, si)
            s = rn.Solver(scene, st)
            c0 = time.process_time()
            s.solve()
            cpu = time.process_time() - c0
            parts = []
            for i in order:
                x = np.asarray(s.corner_radiance(oids[i]), dtype=np.float64)
                if si.objects[i].corner_perm is not None:
                    x = x[si.objects[i].corner_perm]    # solver order -> Blender's
                parts.append(si.objects[i].written_values(x))
            x = np.concatenate(parts)
            if a.save:
                os.makedirs(a.save, exist_ok=True)
                tag = preset + ("" if seed is None else f"_seed{seed}")
                np.savez_compressed(os.path.join(a.save, f"{name}_{tag}.npz"),
                                    corners=x.astype(np.float32), emitter=emit,
                                    objects=np.array(meta["objects"]))
            e = cm.corner_error(x, ref, emitter=emit, ref_var=ref_var)
            stats = s.stats()
            row = {"scene": name, "preset": preset + ("" if seed is None else f" seed {seed}"),
                   **e, "links": stats["links"], "elements": stats["elements"],
                   "rays": stats.get("rays", 0), "seconds": stats["seconds_total"], "cpu": cpu}
            rows.append(row)
            den = (f" (ref. noise removed {e['rrmse_denoised']:.4f})" if "rrmse_denoised" in e else "")
            print(f"{name} {row['preset']}: rRMSE {e['rrmse']:.4f}{den}, NRMSE {e['nrmse']:.4f}, "
                  f"covered share {100 * e['covered_share']:.1f} % ({e['covered']} corners), "
                  f"rRMSE uncovered-only {e['rrmse_uncovered']:.4f}, mean ratio {e['mean_ratio']:.4f}; "
                  f"links {stats['links']} elements {stats['elements']} rays {row['rays']} "
                  f"solve {stats['seconds_total']:.2f} s", flush=True)
            surfaces = cm.per_object(x, ref, meta["objects"], counts, emitter=emit,
                                     floor=cm.scene_floor(ref, emit), keys=("rrmse",))
            print("   ours/ref per surface: " + ", ".join(
                f"{k} {np.mean(v['ours_mean']) / np.mean(v['ref_mean']):.4f}"
                for k, v in surfaces.items() if np.mean(v["ref_mean"]) > 0), flush=True)
            by_preset.setdefault(preset, []).append(x)
            if a.phases:
                if stats.get("gather_points"):
                    print(f"   per output point: {stats['gather_links'] / stats['gather_points']:.0f} links, "
                          f"{stats['gather_rays'] / stats['gather_points']:.0f} rays "
                          f"({stats['gather_near_rays'] / stats['gather_points']:.0f} near field, "
                          f"{stats['gather_lamp_rays'] / stats['gather_points']:.0f} lamps); "
                          f"{stats['gather_points']:,} points, {stats['gather_shared']:,} of them shared", flush=True)
                rays = dict(stats.get("phase_rays", {}))
                print("   phases: " + ", ".join(f"{k} {v:.2f} s ({rays.get(k, 0):,} rays)"
                                               for k, v in stats.get("phases", {}).items()), flush=True)
        for preset, xs in by_preset.items():
            if len(xs) >= 2:
                b = bias_and_noise(xs, ref, ref_var, emit)
                print(f"{name} {preset} over {len(xs)} seeds: one bake's rRMSE {b['single']:.4f} = "
                      f"bias {b['bias']:.4f} (+) solver noise {b['noise']:.4f} (+) reference noise "
                      f"{b['ref_noise']:.4f}, in quadrature", flush=True)
    if a.md:
        write_md(a.md, rows, refs, rn, a.reference)


def bias_and_noise(xs, ref, ref_var, emit):
    """Splits a bake's squared rRMSE (reference noise included) into the solver's bias, its
    noise and the reference's noise, from bakes xs with different seeds: the noise from their
    spread about their mean, the bias from that mean's error less the noises left in it."""
    judged = ~np.asarray(emit, bool)
    r = np.asarray(ref, dtype=np.float64)[judged]
    den = np.maximum(r, cm.scene_floor(ref, emit))
    stack = np.stack([np.asarray(x, dtype=np.float64)[judged] for x in xs])
    k = len(xs)
    mean = stack.mean(axis=0)
    noise2 = float(np.mean(((stack - mean) / den) ** 2) * k / (k - 1))     # one bake's variance
    ref2 = float(np.mean(np.asarray(ref_var, dtype=np.float64)[judged] / den ** 2)) if ref_var is not None else 0.0
    single2 = float(np.mean(((stack - r) / den) ** 2))
    mean_err2 = float(np.mean(((mean - r) / den) ** 2))
    bias2 = max(0.0, mean_err2 - noise2 / k - ref2)
    return {"single": np.sqrt(single2), "bias": np.sqrt(bias2), "noise": np.sqrt(noise2),
            "ref_noise": np.sqrt(ref2)}


def write_md(path, rows, refs, rn, reference):
    f3 = lambda v: "–" if v is None or v != v else f"{v:.4f}"  # noqa: E731
    cmd = "python3 bench/accuracy_native.py " + " ".join(sys.argv[1:])
    md = ["# Accuracy of native full solves against Cycles, every corner judged", "",
          "Command (from the repository root, after the build):", "", f"    {cmd}", "",
          f"Measured {time.strftime('%Y-%m-%d %H:%M')} at commit {git_commit()}, module "
          f"`{os.path.relpath(rn.__file__, ROOT)}`; machine: {os.cpu_count()} cores, load "
          f"{'/'.join(f'{v:.1f}' for v in os.getloadavg())} at the end (shared: seconds are "
          "indicative only).", "",
          "The metric (`bench/corner_metric.py`, the one definition every benchmark and test "
          "uses): every corner but emitters', the corners the Cycles reference reads as exactly 0 "
          "(*covered*: a floor vertex under a box, a box's bottom face on the floor) included. "
          "rRMSE = √mean(((x−r)/max(r, 0.05·mean r))²) over all those corners and channels (the "
          "mean r taken over them too, zeros included; at r = 0 the denominator is that floor), "
          "NRMSE = RMS(x−r)/RMS(r) over the same corners. *Covered share*: the covered corners' "
          "part of rRMSE's squared error (Σ over covered / Σ over all; in brackets the same for "
          "NRMSE's). *rRMSE uncovered-only*: the same formula and floor over the uncovered "
          "corners alone, for comparison with figures from older tables (which left the "
          "covered corners out), never the headline. *Ref. noise removed*: "
          "√max(0, rRMSE² − n²), n the reference's own noise estimated from its independent "
          "parts (per-corner variance of their mean; see the references below).", "",
          "| scene | preset | rRMSE (all) | rRMSE, ref. noise removed | NRMSE (all) | covered "
          "corners | covered share of squared error: rRMSE (NRMSE) | rRMSE uncovered-only | "
          "rRMSE covered-only | mean ours/ref | elements | links | solve s |",
          "|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
    for r in rows:
        md.append(f"| {r['scene']} | {r['preset']} | {f3(r['rrmse'])} | {f3(r.get('rrmse_denoised'))} | "
                  f"{f3(r['nrmse'])} | {r['covered']:,} of {r['judged']:,} | "
                  f"{100 * r['covered_share']:.1f} % ({100 * r['covered_share_abs']:.1f} %) | "
                  f"{f3(r['rrmse_uncovered'])} | {f3(r['rrmse_covered'])} | {r['mean_ratio']:.3f} | "
                  f"{r['elements']:,} | {r['links']:,} | {r['seconds']:.1f} |")
    md += ["", f"References (`{os.path.basename(bt_scenes.ref('SCENE', reference))}`, Cycles "
           f"COMBINED bakes in Blender {'5.x (bpy)' if reference == 'bpy' else '3.4'}, made by "
           f"`python3 bench/tradeoff/run_refs.py --blender {reference}`):", "",
           "| scene | samples | parts (spp × seeds) | Cycles wall s (all parts) | reference noise: "
           "rRMSE | NRMSE | rRMSE uncovered-only |", "|---|---|---|---|---|---|---|"]
    for name, (meta, e) in refs.items():
        parts = meta.get("parts") or [{"samples": meta["samples"], "seed": meta.get("seed")}]
        md.append(f"| {name} | {meta['samples']:,} | "
                  f"{', '.join(str(p['samples']) + ' × seed ' + str(p['seed']) for p in parts)} | "
                  f"{meta.get('seconds', float('nan')):.0f} | {f3(e.get('ref_noise_rrmse'))} | "
                  f"{f3(e.get('ref_noise_nrmse'))} | {f3(e.get('ref_noise_rrmse_uncovered'))} |")
    with open(path, "w") as f:
        f.write("\n".join(md) + "\n")
    print("wrote", path)


if __name__ == "__main__":
    main()
