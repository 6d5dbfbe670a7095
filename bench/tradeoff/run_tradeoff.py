"""Speed/accuracy trade-off of our bake against Cycles on the example scenes: one command.

    python3 bench/tradeoff/run_tradeoff.py [--quick] [--scenes cornell_box box_room ...]
        [--runs 3] [--once-above 40] [--ref-spp 16384] [--part-spp 4096] [--presets ...]
        [--eps ...] [--spp ...] [--zip build/radiosity.zip] [--blender binary|bpy] [--report-only]

Scenes (scenes.py): the four example scenes and the lights room (point, spot, area and sun
lights; bench/tradeoff/scenes/lights_room.blend). For each scene, Blender runs
tradeoff_scene.py: --blender bpy (the default) PyPI's bpy 5.x, with its Cycles as the competitor
and refs/SCENE_cycles5.npz as the reference; --blender binary Debian's Blender 3.4 and
refs/SCENE_cycles.npz (3.4's Cycles reads mesh lamps seen at grazing angles too dark, and its
bakes converge to that: bench/results/reference_bias.md). tradeoff_scene.py does (the cached
Cycles reference, extended to --ref-spp samples in independent parts when it has fewer:
bench/tradeoff/run_refs.py makes them ahead, resumably; our bake at each preset and CUSTOM
epsilon, Cycles at 16..1024 spp, interleaved); the JSON
lands in bench/results/tradeoff_data/SCENE.json. Then report_tradeoff.py (plain python3 with
numpy + matplotlib) writes bench/results/tradeoff.md and bench/results/tradeoff_SCENE.png.
--report-only redoes the tables and plots from the saved JSON.

--quick (for CI: a smoke run, no timing judged): the Cornell box only, DRAFT and 16/64 spp, one
run, the cached reference as it is (never re-made nor extended: a stale one fails the run), or
a 256-spp one (2 parts) in the temporary directory when there is none; everything goes to a temporary
directory (or --out-dir), never over the committed results or references.
"""
import os
import subprocess
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.dirname(os.path.dirname(HERE))
sys.path.insert(0, HERE)
import bt_run  # noqa: E402
import scenes as bt_scenes  # noqa: E402

SCENES = bt_scenes.SCENES
# CUSTOM is MEDIUM (epsilon 0.1, threshold floor 0.1) with another epsilon: the curve around it.
# The finest cost minutes on the bigger rooms (2 cores).
EPS = {"cornell_box": [0.2, 0.05, 0.02], "box_room": [0.2, 0.05, 0.03],
       "chair_room": [0.2, 0.05, 0.03], "full_room": [0.2, 0.05, 0.03],
       "lights_room": [0.2, 0.05, 0.02], "lamp_box": [0.2, 0.05, 0.02]}


def main():
    p = bt_run.driver_parser("run_tradeoff.py")
    p.add_argument("--scenes", nargs="*")
    p.add_argument("--runs", type=int, default=3)
    p.add_argument("--once-above", type=float, default=40.0)
    p.add_argument("--ref-spp", type=int, default=16384)
    p.add_argument("--part-spp", type=int, default=4096)
    p.add_argument("--zip", default=os.path.join(REPO, "build", "radiosity.zip"))
    p.add_argument("--ref-dir", default=os.path.join(HERE, "refs"))
    p.add_argument("--report-only", action="store_true")
    p.add_argument("--presets", nargs="*", help="override: our presets")
    p.add_argument("--eps", nargs="*", type=float, help="override: CUSTOM epsilons")
    p.add_argument("--spp", nargs="*", type=int, help="override: Cycles sample counts")
    p.add_argument("--blender", choices=bt_run.FLAVOURS, default="bpy")
    a = p.parse_args()
    scenes = a.scenes or (["cornell_box"] if a.quick else list(SCENES))
    out_dir = bt_run.results_dir(a.out_dir, a.quick, "tradeoff")
    data_dir = bt_run.data_dir(out_dir, "tradeoff")
    command = "python3 bench/tradeoff/run_tradeoff.py " + " ".join(sys.argv[1:])
    if not a.report_only:
        if not os.path.exists(a.zip):
            raise SystemExit(f"no add-on zip at {a.zip}: build first (see README)")
        t0 = time.perf_counter()
        commit = bt_run.git_commit()
        for s in scenes:
            ref = bt_scenes.ref(s, a.blender, a.ref_dir)
            args = ["--zip", a.zip, "--out", os.path.join(data_dir, f"{s}.json"),
                    "--runs", 1 if a.quick else a.runs, "--once-above", a.once_above]
            if a.quick:
                cached = os.path.exists(ref)
                if not cached:
                    ref = os.path.join(out_dir, f"{s}_cycles_quick.npz")
                args += (["--cached-only"] if cached else
                         ["--ref-spp", 256, "--part-spp", 128])
                args += ["--presets", "DRAFT", "--eps", "--spp", 16, 64]
            else:
                eps = a.eps if a.eps is not None else EPS.get(s, [0.2, 0.05, 0.03])
                args += ["--ref-spp", a.ref_spp, "--part-spp", a.part_spp, "--eps", *eps]
                if a.presets is not None:
                    args += ["--presets", *a.presets]
                if a.spp is not None:
                    args += ["--spp", *a.spp]
            args += ["--ref", ref]
            blend = bt_scenes.blend(s)
            print(f"== {s} ({bt_run.machine()})", flush=True)
            bt_run.run(blend, "tradeoff_scene.py", args,
                       log_path=os.path.join(data_dir, f"{s}.log"), flavour=a.blender)
            bt_run.stamp(os.path.join(data_dir, f"{s}.json"), commit=commit,
                         machine_after=bt_run.machine())
        print(f"all scenes: {time.perf_counter() - t0:.0f} s", flush=True)
    subprocess.run([sys.executable, os.path.join(HERE, "report_tradeoff.py"), "--data", data_dir,
                    "--out-dir", out_dir, "--command", command, "--scenes", *scenes], check=True)
    print(f"results in {out_dir}")


main()
