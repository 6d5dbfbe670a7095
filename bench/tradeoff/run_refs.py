"""Make or extend the cached Cycles references of the trade-off scenes: one command.

    python3 bench/tradeoff/run_refs.py [--scenes cornell_box box_room ...] [--ref-spp 16384]
        [--part-spp 4096] [--min-parts 2] [--ref-dir bench/tradeoff/refs] [--zip build/radiosity.zip]
        [--blender binary|bpy]

Per scene, Debian's Blender 3.4 (--blender binary) or PyPI's bpy 5.x (--blender bpy, the
default: 3.4's Cycles reads mesh lamps seen at grazing angles too dark,
bench/results/reference_bias.md) runs ref_scene.py: independent Cycles bakes (seeds 1, 2, ...) are
added to refs/SCENE_cycles5.npz (bpy; SCENE_cycles.npz: binary) until it holds --ref-spp samples in at least --min-parts parts;
the file keeps every part, their spp-weighted mean and its per-corner variance (the reference's
own noise, bench/corner_metric.py), saved after each part. Run it again to resume or to go
further; a part already there is never baked again. Blender's logs go to
$TMPDIR/SCENE_cycles.log (the facts are in each file's meta).
"""
import argparse
import os
import sys
import tempfile
import time

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.dirname(os.path.dirname(HERE))
sys.path.insert(0, HERE)
import bt_run  # noqa: E402
import scenes as bt_scenes  # noqa: E402


def main():
    p = argparse.ArgumentParser(prog="run_refs.py")
    p.add_argument("--scenes", nargs="*", default=list(bt_scenes.SCENES))
    p.add_argument("--ref-spp", type=int, default=16384)
    p.add_argument("--part-spp", type=int, default=4096)
    p.add_argument("--min-parts", type=int, default=2)
    p.add_argument("--ref-dir", default=os.path.join(HERE, "refs"))
    p.add_argument("--zip", default=os.path.join(REPO, "build", "radiosity.zip"))
    p.add_argument("--blender", choices=bt_run.FLAVOURS, default="bpy")
    a = p.parse_args()
    for s in a.scenes:
        ref = bt_scenes.ref(s, a.blender, a.ref_dir)
        print(f"== {s} ({bt_run.machine()})", flush=True)
        t = time.perf_counter()
        r = bt_run.run(bt_scenes.blend(s), "ref_scene.py",
                       ["--ref", ref, "--zip", a.zip, "--ref-spp", a.ref_spp,
                        "--part-spp", a.part_spp, "--min-parts", a.min_parts],
                       log_path=os.path.join(tempfile.gettempdir(), f"{s}_cycles.log"),
                       flavour=a.blender)
        print(f"   {s}: {r['samples']} spp in {len(r['parts'])} parts, noise {r['noise']}; "
              f"{time.perf_counter() - t:.0f} s", flush=True)


main()
