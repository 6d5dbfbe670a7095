#!/usr/bin/env python3
"""Whether two builds of the solver give the same corners: for a change meant to keep behaviour
(a refactor), run this with the build before and the build after.

    python3 scripts/same_output.py --a /path/to/build-before/native --b build/native \
        [--preset MEDIUM] [--seed 1] [SCENE ...]

Per scene (example scenes by name -- cornell_box, box_room, chair_room, full_room, lights_room,
exported from their .blend in Debian's Blender -- or exported .npz files), each build's module
runs in its own process: a full solve with the given seed, then the scene's stored move
previewed (the live drag's preview) and solved as an update. Every corner value of the three
stages is compared bit for bit; the script prints per scene and stage how many corners differ
and the largest difference, and exits 1 when any does.
"""
import argparse
import os
import subprocess
import sys
import tempfile

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.join(HERE, "..")
SCENES = ("cornell_box", "box_room", "chair_room", "full_room", "lights_room")
STAGES = ("solve", "preview", "update")


def run_one(npz, preset, seed, out):
    """In a child process whose RADIOSITY_NATIVE_DIR names the build: solve, preview, update."""
    sys.path.insert(0, os.path.join(ROOT, "bench"))
    sys.path.insert(0, os.path.join(ROOT, "addon"))
    sys.path.insert(0, os.environ["RADIOSITY_NATIVE_DIR"])
    import radiosity_native as rn
    import accuracy_native
    from radiosity.core import scene_data
    z = np.load(npz)
    si, _ = accuracy_native.scene_input(z)
    scene, _, _ = scene_data.build_native_scene(rn, si)
    st = rn.Settings.preset(preset)
    st.seed = seed
    s = rn.Solver(scene, st)
    s.solve()
    n = len(si.objects)
    res = {"solve": np.concatenate([s.corner_radiance(i).ravel() for i in range(n)])}
    moves = {int(i): np.array(m, dtype=float) for i, m in zip(z["move_ids"].tolist(), z["move_deltas"])} \
        if "move_ids" in z.files else {}
    if moves:
        patches, _ = s.preview(moves)
        res["preview"] = np.concatenate(
            [np.concatenate([c.astype(np.float64), v.ravel()]) for _, (c, v) in sorted(patches.items())]
            or [np.zeros(0)])
        for i, m in moves.items():
            s.move_object(i, np.ascontiguousarray(m))
        s.update()
        res["update"] = np.concatenate([s.corner_radiance(i).ravel() for i in range(n)])
    np.savez(out, **res)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--a", required=True, help="directory of build A's radiosity_native module")
    ap.add_argument("--b", required=True, help="directory of build B's radiosity_native module")
    ap.add_argument("--preset", default="MEDIUM")
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--child", nargs=2, help=argparse.SUPPRESS)
    ap.add_argument("scenes", nargs="*")
    a = ap.parse_args()
    if a.child:
        run_one(a.child[0], a.preset, a.seed, a.child[1])
        return 0
    sys.path.insert(0, os.path.join(ROOT, "bench"))
    import accuracy_native
    differ = False
    with tempfile.TemporaryDirectory() as tmp:
        for name in a.scenes or SCENES:
            npz = name if name.endswith(".npz") else accuracy_native.export(name, tmp)
            got = {}
            for label, native in (("A", a.a), ("B", a.b)):
                out = os.path.join(tmp, f"{os.path.basename(npz)}.{label}.npz")
                env = dict(os.environ, RADIOSITY_NATIVE_DIR=os.path.abspath(native))
                subprocess.run([sys.executable, os.path.abspath(__file__), "--a", a.a, "--b", a.b,
                                "--preset", a.preset, "--seed", str(a.seed), "--child", npz, out],
                               check=True, env=env)
                got[label] = np.load(out)
            for stage in STAGES:
                if stage not in got["A"].files:
                    continue
                x, y = got["A"][stage], got["B"][stage]
                if x.shape != y.shape:
                    print(f"{name} {stage}: {x.size} values against {y.size}")
                    differ = True
                    continue
                bad = int(np.count_nonzero(x != y))
                worst = float(np.max(np.abs(x - y))) if x.size else 0.0
                print(f"{name} {stage}: {x.size} values, {bad} differ (largest difference {worst:.3g})")
                differ |= bad > 0
    print("different" if differ else "identical")
    return 1 if differ else 0


if __name__ == "__main__":
    sys.exit(main())
