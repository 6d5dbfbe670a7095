"""Full solves of the example scenes through the native module only (scenes exported by
bench/export_scene.py): per scene the median time of several runs and the counts (links,
cluster links, elements, element nodes, rays, closed pockets). Compare two builds by pointing
RADIOSITY_NATIVE_DIR at each.

    python3 bench/full_examples.py [--preset MEDIUM] [--runs 3] SCENE.npz ...
"""
import argparse
import glob
import os
import statistics
import time

import numpy as np

from update_examples import build_scene, rn


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--preset", default="MEDIUM")
    ap.add_argument("--runs", type=int, default=1)
    ap.add_argument("scenes", nargs="*")
    a = ap.parse_args()
    for p in a.scenes or sorted(glob.glob("/tmp/*_room.npz")):
        z = np.load(p)
        times, st = [], None
        for _ in range(a.runs):
            s = rn.Solver(build_scene(z), rn.Settings.preset(a.preset))
            t0 = time.perf_counter()
            s.solve()
            times.append(time.perf_counter() - t0)
            st = s.stats()
        print(f"{os.path.basename(p)} {a.preset}: median {statistics.median(times):.3f} s of {a.runs}; links {st['links']} "
              f"cluster {st['cluster_links']} elements {st['elements']} element_nodes {st['element_nodes']} rays {st['rays']} "
              f"links_evaluated {st['links_evaluated']} closed_pockets {st['closed_pockets']} pocket_surfaces {st['pocket_surfaces']}",
              flush=True)


if __name__ == "__main__":
    main()
