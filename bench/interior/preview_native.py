"""The live drag's preview in an exported interior, through the native module alone: one full
solve, then a drag along the benchmark's stored move (the armchair of room 1 and its parts,
moved and turned; --turn adds a turn about the vertical through its centre) in STEPS steps, each a
Solver.preview call as the add-on's timer makes it. What a preview step costs at scale.

    python3 bench/interior/preview_native.py F.npz [PRESET] [--steps 10] [--turn RAD]

F.npz: an export of a make_interior.py scene (see solve_native.py). Prints the solve's wall
time, then per step the preview's wall time and counts (points re-lit, points whose lamps were
re-traced, emitter transfers, rays, points left showing an earlier step, corners written), their
medians, and how far the last step's colours are from a preview of that place with no limit on
its work, over every corner and over the corners of other objects that preview changes.
"""
import argparse
import os
import statistics
import sys
import time

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
from solve_native import solve_export  # noqa: E402


def step_matrix(z, root, f, turn):
    """The stored move of `root` (a rotation about the vertical and a translation) a fraction f
    of the way, then turned f x `turn` about the vertical through the object's centre there."""
    d = np.array(z["move_deltas"][list(z["move_ids"]).index(root)], dtype=float)
    a = f * np.arctan2(d[1, 0], d[0, 0])
    m = np.eye(4)
    m[:2, :2] = [[np.cos(a), -np.sin(a)], [np.sin(a), np.cos(a)]]
    m[:3, 3] = f * d[:3, 3]
    if turn:
        c = z[f"o{root}_vertices"].mean(axis=0) @ m[:3, :3].T + m[:3, 3]
        r, to, back = np.eye(4), np.eye(4), np.eye(4)
        r[:2, :2] = [[np.cos(f * turn), -np.sin(f * turn)], [np.sin(f * turn), np.cos(f * turn)]]
        to[:3, 3], back[:3, 3] = -c, c
        m = back @ r @ to @ m
    return m


def shown_colours(s, n_objects, patches):
    """Every object's corner colours with a preview's patches applied, concatenated."""
    out = []
    for o in range(n_objects):
        c = np.array(s.corner_radiance(o), dtype=np.float64).reshape(-1, 3)
        if o in patches:
            idx, vals = patches[o]
            c[np.asarray(idx)] = vals
        out.append(c.ravel())
    return np.concatenate(out)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("npz")
    ap.add_argument("preset", nargs="?", default="MEDIUM")
    ap.add_argument("--steps", type=int, default=10)
    ap.add_argument("--turn", type=float, default=0.0)
    ap.add_argument("--work", type=int, default=-1, help="Solver.preview's work (-1: Settings.preview_work)")
    a = ap.parse_args()
    z, s, full, names, parts = solve_export(a.npz, a.preset)
    root = int(z["move_ids"][0])
    st = s.stats()
    print(f"{os.path.basename(a.npz)} {a.preset}: full solve {full:.1f} s, {st['gather_points']:,} output points; "
          f"dragged {[names[i] for i in parts]} in {a.steps} steps")
    rows = []
    for k in range(1, a.steps + 1):
        m = step_matrix(z, root, k / a.steps, a.turn)
        t0 = time.perf_counter()
        patches, counts = s.preview({i: m for i in parts}, a.work)
        ms = 1000 * (time.perf_counter() - t0)
        corners = sum(len(c) for c, _ in patches.values())
        rows.append(dict(counts, ms=ms, corners=corners))
        print(f"  step {k}: {ms:.0f} ms, points {counts['points']:,}, lamps {counts['lamps']:,}, "
              f"transfers {counts['transfers']:,}, rays {counts['rays']:,}, deferred {counts['deferred']:,}, "
              f"corners {corners:,}")
    med = {key: statistics.median(r[key] for r in rows) for key in rows[0]}
    print(f"  median: {med['ms']:.0f} ms a step ({1000 / med['ms']:.1f} steps a second), points {med['points']:,.0f}, "
          f"lamps {med['lamps']:,.0f}, rays {med['rays']:,.0f}, corners {med['corners']:,.0f}")
    # What the last step showed against a preview of the same place with no limit on its work
    # (NRMSE over every written corner, the bake's colours where neither patches).
    shown = shown_colours(s, len(names), patches)
    t0 = time.perf_counter()
    full, counts = s.preview({i: m for i in parts}, 0)
    full_ms = 1000 * (time.perf_counter() - t0)
    whole = shown_colours(s, len(names), full)
    base = shown_colours(s, len(names), {})
    rms = lambda v: float(np.sqrt(np.mean(v ** 2)))  # noqa: E731
    moved = shown_colours(s, len(names), {o: p for o, p in full.items() if o not in parts}) != base
    print(f"  the last place previewed in full: {full_ms:.0f} ms, rays {counts['rays']:,}; NRMSE of the last step "
          f"against it {rms(shown - whole) / rms(whole):.4%} (the bake's colours: {rms(base - whole) / rms(whole):.4%}); "
          f"over the {int(moved.sum()) // 3:,} corners of other objects it changes: "
          f"{rms((shown - whole)[moved]) / rms(whole[moved]):.3%} ({rms((base - whole)[moved]) / rms(whole[moved]):.3%})")



if __name__ == "__main__":
    main()
