"""What a native solve holds in memory against what it estimates (Stats.memory_bytes, the
final gather's trace and its forecast), with an optional max_memory_mb:

    python3 bench/interior/memory_native.py SCENE.npz PRESET [NATIVE_DIR] [NAME=VALUE ...]

The process's resident set before the solve, after it and at its peak (VmHWM), beside the
solver's own figures.
"""
import os
import resource
import sys

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.join(HERE, "..", "..")
sys.path.insert(0, os.path.join(ROOT, "bench"))
sys.path.insert(0, os.path.join(ROOT, "addon"))
sys.path.insert(0, sys.argv[3] if len(sys.argv) > 3 and "=" not in sys.argv[3] else os.path.join(ROOT, "build", "native"))
import radiosity_native as rn  # noqa: E402
import accuracy_native  # noqa: E402
from radiosity.core import scene_data  # noqa: E402


def rss_mb():
    with open("/proc/self/status") as f:
        return int(f.read().split("VmRSS:")[1].split()[0]) // 1024


def main():
    si, _ = accuracy_native.scene_input(np.load(sys.argv[1], allow_pickle=True))
    scene, _, _ = scene_data.build_native_scene(rn, si)
    st = rn.Settings.preset(sys.argv[2])
    for kv in [a for a in sys.argv[3:] if "=" in a]:
        k, v = kv.split("=", 1)
        setattr(st, k, type(getattr(st, k))(v))
    before = rss_mb()
    s = rn.Solver(scene, st)
    s.solve()
    t = s.stats()
    mb = lambda k: t.get(k, 0) // 2**20  # noqa: E731
    print(f"RSS before {before} MB, after {rss_mb()} MB, peak "
          f"{resource.getrusage(resource.RUSAGE_SELF).ru_maxrss // 1024} MB; estimate {mb('memory_bytes')} MB "
          f"(trace {mb('gather_bytes')} MB, forecast {mb('gather_forecast_bytes')} MB); capped {t['capped']} "
          f"(memory {t['memory_capped']})")
    print(f"links {t['links']:,}, history {t['history_links']:,}, elements {t['elements']:,}, "
          f"output points {t['gather_points']:,}; warnings {t['warnings']}")


if __name__ == "__main__":
    main()
