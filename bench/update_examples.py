"""Incremental update vs full re-solve on the example scenes, through the native module only
(no Blender): scenes exported by bench/export_scene.py. Prints per scene: full solve time of
the moved scene, update time, ratio, NRMSE between them, the update's phases and link counts.

    python3 bench/update_examples.py [--quick] [--preset MEDIUM] [--runs 3] [--noise] SCENE.npz ...

--noise: also the method's noise floor, the NRMSE between full solves of the moved scene with
Settings.seed 1, 2 and 3 (an update cannot match a full solve more closely than that).

--turn RAD: the stored move, and a turn of RAD radians about the vertical through the object's
centre (the issue's "move plus a 0.4 rad turn").

Each scene also prints the floor under any update that re-computes what a full solve of the
moved scene does (Solver.object_costs): the rays, in that full solve, of the moved objects' own
output points and of their links with the rest of the scene. Every one has an end on a moved
object, so an update casts all of them again; their share of the full solve's rays is the
least an update's ratio can be (history links counted apart: an update may evaluate those only
where un-refinement asks).

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


def moves(z, turn=0.0):
    """{object id: 4x4 world matrix}: the stored move, then a turn about the vertical through
    the moved object's centre."""
    out = {}
    for i, m in zip(z["move_ids"].tolist(), z["move_deltas"]):
        m = np.array(m, dtype=float)
        if turn:
            c = z[f"o{i}_vertices"].mean(axis=0) @ m[:3, :3].T + m[:3, 3]
            r = np.eye(4)
            r[:2, :2] = [[np.cos(turn), -np.sin(turn)], [np.sin(turn), np.cos(turn)]]
            to, back = np.eye(4), np.eye(4)
            to[:3, 3], back[:3, 3] = -c, c
            m = back @ r @ to @ m
        out[int(i)] = m
    return out


def build_scene(z, moved=False, turn=0.0):
    sc = rn.Scene()
    for c in z["clusters"]:
        name, parent = str(c).split("\t")
        sc.add_cluster(name, int(parent))
    deltas = moves(z, turn) if moved else {}
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
    ap.add_argument("--turn", type=float, default=0.0)
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
            for i, m in moves(z, a.turn).items():
                s.move_object(i, np.ascontiguousarray(m))
            t0 = time.perf_counter()
            s.update()
            tu = time.perf_counter() - t0
            su = s.stats()
            f = rn.Solver(build_scene(z, moved=True, turn=a.turn), rn.Settings.preset(a.preset))
            t0 = time.perf_counter()
            f.solve()
            tf = time.perf_counter() - t0
            rows.append((tu, tf, nrmse(corners(s, n), corners(f, n)), su, f.stats(), f.object_costs()))
        rows.sort(key=lambda r: r[0] / r[1])
        tu, tf, e, su, sf, costs = rows[len(rows) // 2]
        turned = f" turned {a.turn} rad" if a.turn else ""
        print(f"{os.path.basename(p)}{turned} {a.preset}: full {tf:.3f} s, update {tu:.3f} s, ratio {100 * tu / tf:.1f} %, "
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
        # Rays are a count the machine's load does not change.
        ru, rf = sum(su["phase_rays"].values()), sum(sf["phase_rays"].values())
        print(f"   rays: update {ru} / full {rf} = {100 * ru / rf:.1f} %")
        moved = sorted(set(z["move_ids"].tolist()))
        own = sum(costs[i]["point_rays"] for i in moved)
        links = sum(costs[i]["link_rays"] for i in moved)
        hist = sum(costs[i]["history_link_rays"] for i in moved)
        print(f"   floor (a full solve's rays with an end on the moved objects): own points {100 * own / rf:.1f} % "
              f"+ gathering links {100 * links / rf:.1f} % = {100 * (own + links) / rf:.1f} %; "
              f"+ history links {100 * hist / rf:.1f} % = {100 * (own + links + hist) / rf:.1f} %")
        print("   update rays by phase:", " ".join(f"{k} {v}" for k, v in su["phase_rays"].items() if v))
        print("   update mode:", su["mode"], "| warnings:", "; ".join(su["warnings"]) or "none")
        print("   update phases:", " ".join(f"{k} {v:.3f}" for k, v in su["phases"].items()))
        print("   full phases:  ", " ".join(f"{k} {v:.3f}" for k, v in sf["phases"].items()), "| iterations", sf["iterations"])


if __name__ == "__main__":
    main()
