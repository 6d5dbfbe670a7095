"""Objects removed and added incrementally vs full solves on the example scenes, through the
native module only (scenes exported by bench/export_scene.py). Per scene the object the scene's
stored move names is removed from a solved scene (Solver.remove_object + update) and compared
with a fresh solve of the scene without it, then added back (Solver.add_object + update) and
compared with a fresh solve of the whole scene. Prints wall-time ratios (one process, same
load), link evaluations and rays of each update against the full solve, and the link counts.

    python3 bench/add_remove_examples.py [--quick] [--preset MEDIUM] SCENE.npz ...

--quick (CI smoke run, no timing judged): DRAFT, and without scenes given the Cornell box exported
from example_blends/cornell_box.blend into a temporary file (bench/quick_scene.py).
"""
import argparse
import os
import sys
import time

import numpy as np

ROOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..")
sys.path.insert(0, os.environ.get("RADIOSITY_NATIVE_DIR", os.path.join(ROOT, "build", "native")))
import radiosity_native as rn  # noqa: E402


def object_args(z, i):
    return (z[f"o{i}_vertices"], z[f"o{i}_loop_starts"], z[f"o{i}_loop_totals"], z[f"o{i}_corner_verts"],
            z[f"o{i}_reflectance"], z[f"o{i}_emission"])


def build_scene(z, skip=None):
    sc = rn.Scene()
    for c in z["clusters"]:
        name, parent = str(c).split("\t")
        sc.add_cluster(name, int(parent))
    for i, o in enumerate(z["objects"]):
        if i == skip:
            continue
        name, cl = str(o).split("\t")
        sc.add_object(name, int(cl), *object_args(z, i))
    return sc


def corners(solver, ids):
    return np.concatenate([solver.corner_radiance(i).ravel() for i in ids])


def nrmse(a, b):
    return float(np.sqrt(np.mean((a - b) ** 2)) / np.sqrt(np.mean(b ** 2)))


def timed(f):
    t0 = time.perf_counter()
    f()
    return time.perf_counter() - t0


def report(what, t_upd, t_full, e, su, w, sf):
    print(f"  {what}: update {t_upd:.3f} s / full {t_full:.3f} s = {100 * t_upd / t_full:.1f} %, NRMSE {100 * e:.2f} %; "
          f"links evaluated {w[0]} ({100 * w[0] / sf['links_evaluated']:.1f} % of the full solve's "
          f"{sf['links_evaluated']}), rays {w[1]} ({100 * w[1] / sf['rays']:.1f} % of {sf['rays']})")
    print(f"    links {su['links']} (full {sf['links']}), elements {su['elements']} (full {sf['elements']}); "
          f"created {su['links_created']}, removed {su['links_removed']}; env-env tested/rejected/rays-clear/"
          f"re-evaluated {su['env_env_links_tested']} {su['env_env_links_rejected']} {su['env_env_links_rays_clear']} "
          f"{su['env_env_links_recomputed']}")
    print("    update phases:", " ".join(f"{k} {v:.3f}" for k, v in su["phases"].items()))


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--quick", action="store_true")
    ap.add_argument("--preset")
    ap.add_argument("scenes", nargs="*")
    a = ap.parse_args()
    a.preset = a.preset or ("DRAFT" if a.quick else "MEDIUM")
    st = rn.Settings.preset(a.preset)
    paths = a.scenes
    if a.quick and not paths:
        import quick_scene
        paths = [quick_scene.export_example("cornell_box")]
    if not paths:
        ap.error("no scenes given (export them with bench/export_scene.py)")
    for p in paths:
        z = np.load(p)
        n = len(z["objects"])
        obj = int(z["move_ids"][0])
        name, cl = str(z["objects"][obj]).split("\t")
        others = [i for i in range(n) if i != obj]
        print(f"{os.path.basename(p)} {a.preset}: '{name}' removed and added back")

        s = rn.Solver(build_scene(z), st)
        t_first = timed(s.solve)
        s0 = s.stats()
        # Removal vs a fresh solve without it (ids after `obj` shift by one there).
        s.remove_object(obj)
        t_rem = timed(s.update)
        sr = s.stats()
        w = (sr["links_evaluated"] - s0["links_evaluated"], sr["rays"] - s0["rays"])
        f = rn.Solver(build_scene(z, skip=obj), st)
        t_f = timed(f.solve)
        report("remove", t_rem, t_f, nrmse(corners(s, others), corners(f, range(n - 1))), sr, w, f.stats())
        # Added back (a new id) vs the first full solve of the whole scene.
        new = s.add_object(name, int(cl), *object_args(z, obj))
        t_add = timed(s.update)
        sa = s.stats()
        w = (sa["links_evaluated"] - sr["links_evaluated"], sa["rays"] - sr["rays"])
        ref = rn.Solver(build_scene(z), st)
        t_ref = timed(ref.solve)
        ids = others[:obj] + [new] + others[obj:]
        report("add", t_add, t_ref, nrmse(corners(s, ids), corners(ref, range(n))), sa, w, ref.stats())
        print(f"  (first full solve {t_first:.3f} s)")


main()
