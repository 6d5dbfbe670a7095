"""The floor under the 15 cm slab (tests/blender/test_gaps.py's gap_slab case) judged natively,
without Blender's bake: for sweeping a preset's settings in seconds.

The scene is built by tests/blender/corner_scenes.py in the PyPI bpy module and exported as the
add-on gathers it (bench/export_scene.py) once, into NPZ; each run solves it with the native
module at PRESET (and NAME=VALUE settings) and prints the test's metric over the floor corners
strictly under the slab: rRMSE relative to max(ref, 0.05 x the floor's mean), the Cycles
reference's own noise removed, and the mean ours / Cycles there.

    python3 bench/gaps_native.py [--native-dir DIR] [--npz /tmp/gap_slab.npz] PRESET [NAME=VALUE ...]
"""
import argparse
import os
import subprocess
import sys

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
REF = os.path.join(ROOT, "tests", "blender", "data", "corner_gap_slab_v4.npy")
HALF = 1.6   # the slab's half width (corner_scenes.build_gap_slab)


def export(npz):
    """corner_scenes' gap_slab, in an empty scene, exported to npz (a bpy subprocess)."""
    code = ("import sys, runpy; sys.path.insert(0, {tb!r}); import bpy; "
            "bpy.ops.wm.read_factory_settings(use_empty=True); import corner_scenes as cs; "
            "cs.build('gap_slab'); sys.argv = ['x', '--', {npz!r}]; "
            "runpy.run_path({exp!r}, run_name='__main__')").format(
        tb=os.path.join(ROOT, "tests", "blender"), npz=npz, exp=os.path.join(HERE, "export_scene.py"))
    subprocess.run([sys.executable, "-c", code], check=True)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--native-dir", default=os.path.join(ROOT, "build", "native"))
    ap.add_argument("--npz", default="/tmp/gap_slab.npz")
    ap.add_argument("preset")
    ap.add_argument("settings", nargs="*", metavar="NAME=VALUE")
    a = ap.parse_args()
    if not os.path.exists(a.npz):
        export(a.npz)
    sys.path.insert(0, a.native_dir)
    sys.path.insert(0, HERE)
    sys.path.insert(0, os.path.join(ROOT, "addon"))
    import radiosity_native as rn
    from accuracy_native import apply_settings, scene_input
    from radiosity.core import scene_data

    si, _ = scene_input(np.load(a.npz))
    st = rn.Settings.preset(a.preset)
    apply_settings(st, a.settings)
    scene, _, oids = scene_data.build_native_scene(rn, si)
    s = rn.Solver(scene, st)
    s.solve()
    xs, pos, obj = [], [], []
    for i, o in enumerate(si.objects):       # Floor, then Slab: the reference's order
        x = np.asarray(s.corner_radiance(oids[i]), dtype=np.float64).reshape(-1, 3)
        if o.corner_perm is not None:
            x = x[o.corner_perm]
        xs.append(x)
        pos.append(o.vertices[o.corner_verts])
        obj += [o.name] * len(x)
    x, pos, obj = np.concatenate(xs), np.concatenate(pos), np.array(obj)
    ref, noise = np.load(REF).astype(np.float64)
    under = (obj == "Floor") & (np.abs(pos[:, 0]) < HALF - 1e-6) & (np.abs(pos[:, 1]) < HALF - 1e-6)
    scale = np.maximum(ref[under], 0.05 * ref[obj == "Floor"].mean())
    e = float(np.sqrt(np.mean(((x[under] - ref[under]) / scale) ** 2)))
    nz = float(np.sqrt(np.mean((noise[under] / scale) ** 2)))
    stats = s.stats()
    print(f"{a.preset} {' '.join(a.settings)}: {int(under.sum())} floor corners under the slab, rRMSE "
          f"{e:.4f} (noise removed {np.sqrt(max(e * e - nz * nz, 0.0)):.4f}), mean ours/Cycles "
          f"{x[under].mean() / ref[under].mean():.3f}; links {stats['links']:,}, elements "
          f"{stats['elements']:,}, rays {stats['rays']:,}")


if __name__ == "__main__":
    main()
