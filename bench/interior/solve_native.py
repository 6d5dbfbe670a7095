"""One full solve of an exported scene through the native module alone (no Blender), with the
solver's stats and its phases (seconds and rays): where a bake's time goes, and how many links,
elements, output points and rays it takes, without the add-on around it.

    python3 bench/export_scene.py-style export first, e.g. in PyPI bpy:
      python3 -c "import bpy, runpy, sys; bpy.ops.wm.open_mainfile(filepath='F.blend'); \\
                  sys.argv = ['x', '--', 'F.npz']; runpy.run_path('bench/export_scene.py', run_name='__main__')"
    python3 bench/interior/solve_native.py F.npz [PRESET] [NAME=VALUE ...] [--save OUT.npz]

NAME=VALUE overrides a Settings field (e.g. gather_min_rays=1); --save writes every written
object's corner radiance (one array per object, "o<index>") to compare two solves with
bench/interior/compare_solves.py. The scene is built by the
add-on's own core (objects, lights, world), as bench/accuracy_native.py does.
"""
import os
import resource
import sys
import time

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.join(HERE, "..", "..")
sys.path.insert(0, os.path.join(ROOT, "bench"))
sys.path.insert(0, os.path.join(ROOT, "addon"))
sys.path.insert(0, os.environ.get("RADIOSITY_NATIVE_DIR", os.path.join(ROOT, "build", "native")))
import radiosity_native as rn  # noqa: E402
import accuracy_native  # noqa: E402  (scene_input: the exported arrays as the add-on's SceneInput)
from radiosity.core import scene_data  # noqa: E402


def solve_export(path, preset):
    """An exported interior solved at `preset`, as the update and preview benchmarks start:
    (its arrays, the solver, the solve's wall seconds, the objects' names, the moved object's
    parts: the stored move's root and the objects named after it, "Armchair back" for
    "Armchair", which move with it as the add-on moves a collection)."""
    z = np.load(path)
    si, _ = accuracy_native.scene_input(z)
    scene, _, _ = scene_data.build_native_scene(rn, si)
    s = rn.Solver(scene, rn.Settings.preset(preset))
    t0 = time.time()
    s.solve()
    seconds = time.time() - t0
    names = [str(o).split("\t")[0] for o in z["objects"]]
    root = int(z["move_ids"][0])
    parts = [i for i, n in enumerate(names) if n.split(" ")[0] == names[root]]
    return z, s, seconds, names, parts


def main():
    args = sys.argv[1:]
    save = None
    if "--save" in args:
        k = args.index("--save")
        save = args[k + 1]
        del args[k:k + 2]
    path = args[0]
    preset = args[1] if len(args) > 1 else "DRAFT"
    st = rn.Settings.preset(preset)
    for kv in args[2:]:
        k, v = kv.split("=", 1)
        t = type(getattr(st, k))
        setattr(st, k, v.lower() in ("1", "true", "yes", "on") if t is bool else t(v))
    si, written = accuracy_native.scene_input(np.load(path))
    scene, _, _ = scene_data.build_native_scene(rn, si)
    s = rn.Solver(scene, st)
    w0, c0 = time.time(), time.process_time()
    s.solve()
    wall, cpu = time.time() - w0, time.process_time() - c0
    stats = s.stats()
    print(f"{os.path.basename(path)} {preset}: wall {wall:.1f} s, CPU {cpu:.1f} s, peak RSS "
          f"{resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024:.0f} MB; objects {len(written)} "
          f"({sum(written)} written)")
    keys = ("input_surfaces", "elements", "links", "cluster_links", "surface_links", "obj_obj_links",
            "history_links", "occluded_links", "capped", "iterations", "refine_rounds", "rays",
            "gather_points", "gather_corners", "gather_links", "gather_rays", "gather_near", "gather_near_rays",
            "gather_lamp_rays", "gather_shared", "memory_bytes", "gather_bytes", "gather_forecast_bytes", "memory_capped")
    print("  " + ", ".join(f"{k} {stats[k]:,}" if isinstance(stats[k], int) and not isinstance(stats[k], bool)
                            else f"{k} {stats[k]}" for k in keys if k in stats))
    if stats.get("gather_points"):
        print(f"  per output point: {stats['gather_links'] / stats['gather_points']:.0f} links, "
              f"{stats['gather_rays'] / stats['gather_points']:.0f} rays")
    rays = dict(stats.get("phase_rays", {}))
    print("  phases: " + ", ".join(f"{k} {v:.1f} s ({rays.get(k, 0):,} rays)"
                                   for k, v in stats.get("phases", {}).items()))
    if save:
        np.savez_compressed(save, **{f"o{i}": np.asarray(s.corner_radiance(i), dtype=np.float32)
                                     for i, w in enumerate(written) if w})


if __name__ == "__main__":
    main()
