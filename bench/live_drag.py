"""Live drag benchmark: a scripted drag of an example scene's stored move with Live
on, through the add-on in Blender, as a user's drag drives it.

    python3 bench/live_drag.py [--blend example_blends/box_room.blend] [--preset MEDIUM]
        [--steps 30] [--runs 3] [--out bench/results/live_drag.md]
    (or: blender -b --factory-startup --python bench/live_drag.py -- ARGS)

--quick (CI smoke run, nothing judged): the Cornell box at DRAFT, 3 steps, one run, no report file.

python3 must import bpy (PyPI's bpy 5.x); the add-on comes from build/addon/stage (the build's
staged package with the native module). Per run: open the file, bake (Live on), then N steps
from the object's place to scene["radiosity_move"]'s (location and turn shared evenly): each
step sets the object's matrix, lets the depsgraph evaluate (our depsgraph_update_post handler
sees the move) and runs radiosity.preview_now() (what the add-on's timer runs in the UI, which
writes the preview's colours). After the last step, radiosity.pump() runs the update the UI
starts once the drag pauses (core.live.DEBOUNCE_SECONDS after the last move); then a full bake
(full=True) of the final place, the reference.

Reported (medians over runs): the main thread's time per step (move, depsgraph, preview,
colour write) and the rate it allows; how many steps changed the colours; the update's time
after the pause (+ the debounce: when the colours equal the full bake); NRMSE against the full
bake of the colours before the drag, of the last preview and of the update. Viewport drawing is
not included (there is none in background mode).
"""
import argparse
import math
import os
import statistics
import sys
import time

import bpy
import numpy as np

REPO = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def parse():
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else sys.argv[1:]
    p = argparse.ArgumentParser(prog="live_drag.py")
    p.add_argument("--blend", default=os.path.join(REPO, "example_blends", "box_room.blend"))
    p.add_argument("--preset", default="MEDIUM")
    p.add_argument("--steps", type=int, default=30)
    p.add_argument("--runs", type=int, default=3)
    p.add_argument("--out", help="append the report (markdown) to this file")
    p.add_argument("--addon-dir", default=os.path.join(REPO, "build", "addon", "stage"))
    p.add_argument("--quick", action="store_true")
    a = p.parse_args(argv)
    if a.quick:
        a.blend = os.path.join(REPO, "example_blends", "cornell_box.blend")
        a.preset, a.steps, a.runs, a.out = "DRAFT", 3, 1, None
    return a


def colours(attr):
    return sys.modules["radiosity"].writer.read_colours(bpy.context.scene, attr)


def flat(c):
    return np.concatenate([c[k] for k in sorted(c)])


def nrmse(a, b):
    x, y = flat(a), flat(b)
    return float(np.sqrt(np.mean((x - y) ** 2)) / np.sqrt(np.mean(y ** 2)))


def moved_objects(scene):
    mv = scene["radiosity_move"]
    name = mv["object"]
    if name in bpy.data.objects:
        return [bpy.data.objects[name]], mv
    return [o for o in bpy.data.collections[name].all_objects if o.parent is None], mv


def one_run(args, mod):
    bpy.ops.wm.open_mainfile(filepath=os.path.abspath(args.blend))
    scene = bpy.context.scene
    props = scene.radiosity
    props.preset = args.preset
    attr = props.attribute_name
    t0 = time.perf_counter()
    bpy.ops.radiosity.bake()
    bake_s = time.perf_counter() - t0
    props.live = True
    bpy.context.view_layer.update()
    before = colours(attr)
    objs, mv = moved_objects(scene)
    start = [(np.array(o.location), o.rotation_euler.z) for o in objs]
    delta = np.array(mv["location"], dtype=float) - np.array(objs[0].location)
    turn = math.radians(float(mv.get("rotation_z_deg", 0.0)))
    step_s, changed, counts = [], 0, []
    previous = before
    for k in range(1, args.steps + 1):
        f = k / args.steps
        t = time.perf_counter()
        for o, (loc, rz) in zip(objs, start):
            o.location = tuple(loc + delta * f)
            o.rotation_euler.z = rz + turn * f
        bpy.context.view_layer.update()
        shown = mod.preview_now()
        step_s.append(time.perf_counter() - t)
        now = colours(attr)
        changed += int(shown > 0 and any(not np.array_equal(now[n], previous[n]) for n in now))
        previous = now
        st = next(iter(mod.core.session.sessions().values())).live
        counts.append(dict(st.last_preview or {}))
    last_preview = previous
    t = time.perf_counter()
    runs = mod.pump(timeout=900)
    update_s = time.perf_counter() - t
    import json
    stats = json.loads(props.last_stats)
    after = colours(attr)
    t = time.perf_counter()
    bpy.ops.radiosity.bake(full=True)
    full_s = time.perf_counter() - t
    full = colours(attr)
    return {"bake_s": bake_s, "step_s": step_s, "changed": changed, "updates": runs,
            "update_s": update_s, "full_s": full_s, "mode": stats.get("mode"),
            "nrmse_before": nrmse(before, full), "nrmse_preview": nrmse(last_preview, full),
            "nrmse_update": nrmse(after, full),
            "preview_rays": statistics.median(c.get("rays", 0) for c in counts),
            "preview_points": statistics.median(c.get("points", 0) for c in counts),
            "errors": list(mod.handlers.last_errors)}


def main():
    args = parse()
    sys.path.insert(0, os.path.abspath(args.addon_dir))
    import radiosity
    radiosity.register()
    mod = radiosity
    rows = [one_run(args, mod) for _ in range(args.runs)]
    med = lambda key: statistics.median(r[key] for r in rows)  # noqa: E731
    step_med = statistics.median(s for r in rows for s in r["step_s"])
    step_p90 = sorted(s for r in rows for s in r["step_s"])[int(0.9 * sum(len(r["step_s"]) for r in rows))]
    debounce = mod.core.live.DEBOUNCE_SECONDS
    scene = os.path.splitext(os.path.basename(args.blend))[0]
    lines = [
        f"**{time.strftime('%Y-%m-%d %H:%M UTC', time.gmtime())}, {scene}, {args.preset}, "
        f"{args.steps} steps, medians of {args.runs} runs** (Blender {bpy.app.version_string}; "
        f"command: `python3 bench/live_drag.py {' '.join(sys.argv[1:])}`)",
        "",
        "| figure | value |",
        "|---|---|",
        f"| main thread per drag step (move, depsgraph, preview, write): median / 90th pct | "
        f"{step_med * 1000:.0f} / {step_p90 * 1000:.0f} ms |",
        f"| colour changes per second that allows | {1 / step_med:.1f} |",
        f"| steps whose colours changed | {med('changed'):.0f} of {args.steps} |",
        f"| preview per step: points re-lit, rays (median) | {med('preview_points'):.0f}, "
        f"{med('preview_rays'):.0f} |",
        f"| update after the pause | {med('update_s'):.2f} s (+ {debounce} s debounce: equal "
        f"after {med('update_s') + debounce:.2f} s) |",
        f"| full bake of the final place | {med('full_s'):.2f} s (first bake {med('bake_s'):.2f} s) |",
        f"| NRMSE vs that full bake: before the drag / last preview / update | "
        f"{med('nrmse_before') * 100:.2f} / {med('nrmse_preview') * 100:.2f} / "
        f"{med('nrmse_update') * 100:.2f} % |",
        f"| update mode; errors | {rows[0]['mode']}; {sum(len(r['errors']) for r in rows)} |",
        "",
    ]
    text = "\n".join(lines)
    print(text)
    if args.out:
        with open(args.out, "a") as f:
            f.write(text + "\n")


main()
