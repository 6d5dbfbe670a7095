"""Incremental update vs full re-solve on the example scenes, through the native module only
(no Blender): scenes exported by bench/export_scene.py. Prints per scene: full solve time of
the moved scene, update time, ratio, NRMSE between them, the update's phases and link counts.

    python3 bench/update_examples.py [--quick] [--preset MEDIUM] [--runs 3] [--noise] SCENE.npz ...

--noise: also the method's noise floor, the NRMSE between full solves of the moved scene with
Settings.seed 1, 2 and 3 (an update cannot match a full solve more closely than that).

--quick (CI smoke run, no timing judged): DRAFT, one run, and without scenes given the Cornell box
exported from example_blends/cornell_box.blend into a temporary file (bench/quick_scene.py).
"""
import argparse
import glob
import os
import sys
import time

import numpy as np

ROOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..")
sys.path.insert(0, os.environ.get("RADIOSITY_NATIVE_DIR", os.path.join(ROOT, "build", "native")))
import radiosity_native as rn  # noqa: E402


def build_scene(z, moved=False):
    sc = rn.Scene()
    for c in z["clusters"]:
        name, parent = str(c).split("\t")
        sc.add_cluster(name, int(parent))
    deltas = dict(zip(z["move_ids"].tolist(), z["move_deltas"])) if moved else {}
    for i, o in enumerate(z["objects"]):
        name, cl = str(o).split("\t")
        v = z[f"o{i}_vertices"]
        if i in deltas:
            m = deltas[i]
            v = v @ m[:3, :3].T + m[:3, 3]
        sc.add_object(name, int(cl), np.ascontiguousarray(v), z[f"o{i}_loop_starts"], z[f"o{i}_loop_totals"],
                      z[f"o{i}_corner_verts"], z[f"o{i}_reflectance"], z[f"o{i}_emission"])
    return sc


def corners(s, n):
    return np.concatenate([s.corner_radiance(i).ravel() for i in range(n)])


def nrmse(a, b):
    return float(np.sqrt(np.mean((a - b) ** 2)) / np.sqrt(np.mean(b ** 2)))


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--quick", action="store_true")
    ap.add_argument("--preset")
    ap.add_argument("--runs", type=int)
    ap.add_argument("--noise", action="store_true")
    ap.add_argument("scenes", nargs="*")
    a = ap.parse_args()
    a.preset = a.preset or ("DRAFT" if a.quick else "MEDIUM")
    a.runs = max(1, a.runs or 1)
    paths = a.scenes or sorted(glob.glob("/tmp/*_room.npz"))
    if a.quick and not a.scenes:
        import quick_scene
        paths = [quick_scene.export_example("cornell_box")]
    if not paths:
        raise SystemExit("no scenes: export them with bench/export_scene.py (see its docstring)")
    for p in paths:
        z = np.load(p)
        n = len(z["objects"])
        rows = []
        for _ in range(a.runs):
            s = rn.Solver(build_scene(z), rn.Settings.preset(a.preset))
            s.solve()
            for i, m in zip(z["move_ids"].tolist(), z["move_deltas"]):
                s.move_object(int(i), np.ascontiguousarray(m))
            t0 = time.perf_counter()
            s.update()
            tu = time.perf_counter() - t0
            su = s.stats()
            f = rn.Solver(build_scene(z, moved=True), rn.Settings.preset(a.preset))
            t0 = time.perf_counter()
            f.solve()
            tf = time.perf_counter() - t0
            rows.append((tu, tf, nrmse(corners(s, n), corners(f, n)), su, f.stats()))
        rows.sort(key=lambda r: r[0] / r[1])
        tu, tf, e, su, sf = rows[len(rows) // 2]
        print(f"{os.path.basename(p)} {a.preset}: full {tf:.3f} s, update {tu:.3f} s, ratio {100 * tu / tf:.1f} %, "
              f"NRMSE {100 * e:.2f} %; links {sf['links']} full / {su['links']} upd, elements {sf['elements']} / {su['elements']}")
        print("   env-env tested/rejected/rays-clear/recomputed (live + history)", su["env_env_links_tested"],
              su["env_env_links_rejected"], su["env_env_links_rays_clear"],
              f"{su['env_env_links_recomputed']} + {su['history_links_recomputed']}", "| iterations", su["iterations"],
              "rounds", su["refine_rounds"])
        if a.noise:
            sols = []
            for seed in (1, 2, 3):
                st = rn.Settings.preset(a.preset)
                st.seed = seed
                g = rn.Solver(build_scene(z, moved=True), st)
                g.solve()
                sols.append(corners(g, n))
            print("   noise floor (full solves, seeds 1-2, 1-3, 2-3): NRMSE",
                  " ".join(f"{100 * nrmse(sols[i], sols[j]):.2f} %" for i, j in ((0, 1), (0, 2), (1, 2))))
        # Rays are a count the machine's load does not change. Re-linking the moved objects
        # (relink) is work every update must do (their links' form factors all change): its
        # share of a full solve's rays is a floor for the ratio above.
        ru, rf = sum(su["phase_rays"].values()), sum(sf["phase_rays"].values())
        print(f"   rays: update {ru} / full {rf} = {100 * ru / rf:.1f} %; re-linking the moved objects alone "
              f"{100 * su['phase_rays'].get('relink', 0) / rf:.1f} % (a floor)")
        print("   update rays by phase:", " ".join(f"{k} {v}" for k, v in su["phase_rays"].items() if v))
        print("   update mode:", su["mode"], "| warnings:", "; ".join(su["warnings"]) or "none")
        print("   update phases:", " ".join(f"{k} {v:.3f}" for k, v in su["phases"].items()))
        print("   full phases:  ", " ".join(f"{k} {v:.3f}" for k, v in sf["phases"].items()), "| iterations", sf["iterations"])


if __name__ == "__main__":
    main()
