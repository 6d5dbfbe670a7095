"""Error breakdown of one bake against the cached Cycles reference (see diag_scene.py).

    python3 bench/tradeoff/run_diag.py --scene cornell_box --preset HIGH [--eps 0.02]
        [--out bench/results/tradeoff_diag_SCENE_PRESET.md]
"""
import argparse
import json
import os
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.dirname(os.path.dirname(HERE))
sys.path.insert(0, HERE)
import bt_run  # noqa: E402
import scenes as bt_scenes  # noqa: E402


def main():
    p = argparse.ArgumentParser()
    p.add_argument("--scene", required=True)
    p.add_argument("--preset", default="HIGH")
    p.add_argument("--eps", type=float)
    p.add_argument("--zip", default=os.path.join(REPO, "build", "radiosity.zip"))
    p.add_argument("--out")
    a = p.parse_args()
    ref = bt_scenes.ref(a.scene)
    tmp = os.path.join(tempfile.mkdtemp(prefix="diag-"), "diag.json")
    args = ["--zip", a.zip, "--ref", ref, "--preset", a.preset, "--out", tmp]
    if a.eps:
        args += ["--eps", a.eps]
    bt_run.run(bt_scenes.blend(a.scene), "diag_scene.py", args)
    d = json.load(open(tmp))
    out = a.out or os.path.join(REPO, "bench", "results", f"tradeoff_diag_{a.scene}_{a.preset}.md")
    lines = [f"# Where the error comes from: {a.scene} at {a.preset}"
             + (f" (ε {a.eps})" if a.eps else ""), "",
             "Command:", "", "    python3 bench/tradeoff/run_diag.py " + " ".join(sys.argv[1:]), "",
             f"One bake ({d['seconds']:.1f} s, {d['elements']:,} elements) against the cached Cycles "
             f"reference, same corners and measures as bench/results/tradeoff.md (bench/corner_metric.py: "
             f"every corner but emitters', covered ones included). All: rRMSE "
             f"{d['all']['rrmse']:.4f}, NRMSE {d['all']['nrmse']:.4f}; without the corners within "
             f"0.02 scene diagonals of the light: rRMSE {d['without_near_light']['rrmse']:.4f}, "
             f"NRMSE {d['without_near_light']['nrmse']:.4f}.", "",
             "Share of the squared error (what each group contributes to NRMSE² and rRMSE²), and the "
             "group's own errors (the scene's floor); groups are covered / uncovered corners, object × the axis the polygon faces (-z = facing "
             "down: a ceiling), then distance bands from the light's bounding box.", "",
             "| group | corners | share of NRMSE² | share of rRMSE² | rRMSE | NRMSE | mean ours/ref |",
             "|---|---|---|---|---|---|---|"]
    for r in d["groups"]:
        lines.append(f"| {r['group']} | {r['corners']:,} | {100 * r['share_nrmse_sq']:.1f} % | "
                     f"{100 * r['share_rrmse_sq']:.1f} % | {r['rrmse']:.3f} | {r['nrmse']:.3f} | "
                     f"{r['mean_ratio']:.3f} |")
    with open(out, "w") as f:
        f.write("\n".join(lines) + "\n")
    print("\n".join(lines))


main()
