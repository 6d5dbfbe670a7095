"""One full solve of an exported interior and one incremental update after the benchmark's move
(the armchair of room 1 and its parts moved by the scene's stored move and turned about the
vertical through its centre), through the native module alone: where an update's time goes.

    python3 bench/interior/update_native.py F.npz [PRESET] [--turn RAD]

F.npz: an export of a make_interior.py scene (see solve_native.py). Prints the solve's and the
update's wall times, the update's ratio to the solve and its phases (seconds and rays).
"""
import argparse
import os
import resource
import sys
import time

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
# The native module, the add-on's core and accuracy_native, found as solve_native finds them.
from solve_native import solve_export  # noqa: E402
import update_examples  # noqa: E402  (moves: the stored move plus a turn; bench/ is on the path)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("npz")
    ap.add_argument("preset", nargs="?", default="MEDIUM")
    ap.add_argument("--turn", type=float, default=0.6)
    a = ap.parse_args()
    z, s, full, names, parts = solve_export(a.npz, a.preset)
    peak_full = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024
    (root, m), = update_examples.moves(z, a.turn).items()
    for i in parts:
        s.move_object(i, np.ascontiguousarray(m))
    t0 = time.time()
    s.update()
    upd = time.time() - t0
    st = s.stats()
    rays = dict(st.get("phase_rays", {}))
    peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024
    print(f"{os.path.basename(a.npz)} {a.preset}: full {full:.1f} s, update {upd:.1f} s "
          f"({100 * upd / full:.0f} % of the full solve), moved {[names[i] for i in parts]}; "
          f"peak RSS {peak_full:.0f} MB after the solve, {peak:.0f} MB after the update")
    print("  update phases: " + ", ".join(f"{k} {v:.1f} s ({rays.get(k, 0):,} rays)"
                                          for k, v in st.get("phases", {}).items()))
    print("  output: " + ", ".join(f"{k} {st[k]:,}" for k in (
        "gather_points", "gather_fresh_points", "gather_kept", "gather_replayed", "gather_rays",
        "gather_lamp_rays", "gather_near_rays", "gather_shared")))
    # (Counts a build before them does not have: '-'.)
    print("  probes and contacts: " + ", ".join(f"{k} {st[k]:,}" if k in st else f"{k} -" for k in (
        "gather_probe_rays", "gather_probes_kept", "contact_surfaces")) + (f", seconds_contacts {st['seconds_contacts']:.3f}"
                                                     if "seconds_contacts" in st else ""))
    print("  solution: " + ", ".join(f"{k} {st[k]:,}" if isinstance(st[k], int) else f"{k} {st[k]:.2f}" for k in (
        "links", "links_created", "iterations", "link_sweeps", "seconds_sweeps", "gather_plans",
        "seconds_gather_plan", "refine_rounds")))


if __name__ == "__main__":
    main()
