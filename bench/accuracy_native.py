"""Accuracy of native full solves against the cached Cycles references, without Blender.

A quick check for solver changes: the example scenes exported by bench/export_scene.py are
solved through the native module at each preset, and compared over the same corners and with
the same measures as bench/tradeoff (rRMSE = sqrt(mean(((x-r)/max(r, 0.05 mean r))^2)), NRMSE;
emitters' corners and those the reference has at 0 left out). Objects are matched by name
(the references store them sorted by name).

    python3 bench/accuracy_native.py [--native-dir DIR] [--presets DRAFT,MEDIUM] [--seeds 1,2,3]
                                     [--set rays_per_link=64 ...] SCENE.npz ...

The reference of SCENE.npz is bench/tradeoff/refs/SCENE_cycles.npz. --native-dir picks another
build (e.g. a worktree at the commit before a change) to compare two builds on the same scenes.
"""
import argparse
import json
import os
import sys

import numpy as np

ROOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..")


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--native-dir", default=os.path.join(ROOT, "build", "native"))
    ap.add_argument("--presets", default="DRAFT,MEDIUM")
    ap.add_argument("--seeds", default="", help="comma-separated Settings.seed values (default: the preset's)")
    ap.add_argument("--set", action="append", default=[], metavar="NAME=VALUE",
                    help="override a Settings field, e.g. --set rays_per_link=64 (repeatable)")
    ap.add_argument("scenes", nargs="+")
    a = ap.parse_args()
    os.environ["RADIOSITY_NATIVE_DIR"] = a.native_dir
    sys.path.insert(0, os.path.join(ROOT, "bench"))
    import update_examples as ue  # imports the module from RADIOSITY_NATIVE_DIR
    rn = ue.rn
    print("module:", rn.__file__)
    for path in a.scenes:
        name = os.path.splitext(os.path.basename(path))[0]
        z = np.load(path)
        refz = np.load(os.path.join(ROOT, "bench", "tradeoff", "refs", f"{name}_cycles.npz"), allow_pickle=True)
        ref = refz["corners"]
        meta = json.loads(str(refz["meta"]))
        n = len(z["objects"])
        names = [str(o).split("\t")[0] for o in z["objects"]]
        order = sorted(range(n), key=lambda i: names[i])
        if [names[i] for i in order] != meta["objects"]:
            raise SystemExit(f"{name}: objects {sorted(names)} differ from the reference's {meta['objects']}")
        emit = np.concatenate([np.repeat(np.any(z[f"o{i}_emission"] > 0, axis=1), z[f"o{i}_loop_totals"]) for i in order])
        keep = ~emit & np.all(ref > 0, axis=1)
        r = ref[keep]
        for preset, seed in [(p, sd) for p in a.presets.split(",") for sd in (a.seeds.split(",") if a.seeds else [None])]:
            st = rn.Settings.preset(preset)
            if seed is not None:
                st.seed = int(seed)
            for kv in a.set:
                k, v = kv.split("=", 1)
                t = type(getattr(st, k))
                setattr(st, k, v.lower() in ("1", "true", "yes", "on") if t is bool else t(v))
            s = rn.Solver(ue.build_scene(z), st)
            s.solve()
            x = np.concatenate([s.corner_radiance(i) for i in order])[keep]
            rrmse = float(np.sqrt(np.mean(((x - r) / np.maximum(r, 0.05 * r.mean())) ** 2)))
            nrmse = float(np.sqrt(np.mean((x - r) ** 2)) / np.sqrt(np.mean(r ** 2)))
            st = s.stats()
            print(f"{name} {preset}{'' if seed is None else ' seed ' + seed}: rRMSE {rrmse:.4f} NRMSE {nrmse:.4f} mean ratio {x.mean() / r.mean():.4f} "
                  f"links {st['links']} elements {st['elements']} rays {st.get('rays', 0)} solve {st['seconds_total']:.2f} s")


if __name__ == "__main__":
    main()
