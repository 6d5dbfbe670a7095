"""The paper's Table 2 row for one example .blend, inside Blender (started by run_table2.py).

    blender -b --factory-startup SCENE.blend --python bench/tradeoff/table2_scene.py -- \
        --zip build/radiosity.zip --out OUT.json [--preset MEDIUM] [--runs 1] [--drag-steps 30]

1. Full bake through the add-on (bpy.ops.radiosity.bake(full=True)): the counts and seconds.
2. Full solve with and without the paper's 3.5 strategy: the add-on has no setting for
   `progressive_refinement`, so the scene is gathered with the add-on's own gather path
   (radiosity.gather + core.scene_data.build_native_scene) and solved by the native module
   directly, both ways, interleaved (--runs times each).
3. The stored move (scene["radiosity_move"]): incremental re-bake (full=False) from the full
   bake, then a full bake of the moved scene; NRMSE between the two (all corners), both times.
   --runs times (the add-on keeps the solution, so each run is: back to the start with a full
   bake, move, incremental, full).
4. A drag: the same move in --drag-steps equal steps, an incremental re-bake after each; then a
   full bake of the final placement: median step time / full time, NRMSE final vs full
   (--drag-preset: a cheaper preset for the drag on a busy machine).
"""
import argparse
import os
import statistics
import sys
import time

import bpy
import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import bt_common as bt  # noqa: E402

KEYS = ("input_surfaces", "objects", "clusters", "elements", "links", "cluster_links",
        "obj_env_links", "env_env_links", "obj_obj_links", "rays", "seconds", "seconds_total",
        "seconds_adjust", "env_env_links_tested", "env_env_links_rejected",
        "env_env_links_recomputed", "history_links_recomputed", "avoided_by_progressive", "history_links", "mode",
        "full_reason")


def parse():
    p = argparse.ArgumentParser(prog="table2_scene.py")
    p.add_argument("--zip", required=True)
    p.add_argument("--out", required=True)
    p.add_argument("--preset", default="MEDIUM")
    p.add_argument("--runs", type=int, default=1)
    p.add_argument("--drag-steps", type=int, default=30)
    p.add_argument("--drag-preset", help="preset of the drag (default: --preset)")
    return p.parse_args(bt.args())


def pick(st):
    return {k: st.get(k) for k in KEYS}


def nrmse(x, r):
    return float(np.sqrt(np.mean((x - r) ** 2)) / np.sqrt(np.mean(r ** 2)))


def native_solves(preset, runs):
    """Native full solves of the gathered scene with and without 3.5, interleaved."""
    from radiosity import bake as addon_bake, gather
    from radiosity.core import presets, scene_data
    native = addon_bake.load_native()
    scene = bpy.context.scene
    si, _, _ = gather.gather(scene, bpy.context.view_layer, bpy.context.evaluated_depsgraph_get())
    out = {True: [], False: []}
    for _ in range(runs):
        for prog in (True, False):
            nscene, _, _ = scene_data.build_native_scene(native, si)
            st = presets.make_settings(native, preset)
            st.progressive_refinement = prog
            solver = native.Solver(nscene, st)
            t = time.perf_counter()
            solver.solve()
            sec = time.perf_counter() - t
            s = solver.stats()
            out[prog].append({"seconds": sec, "elements": s["elements"], "links": s["links"],
                              "avoided_by_progressive": s["avoided_by_progressive"],
                              "rays": s["rays"]})
            bt.log(f"native solve, 3.5 {'on' if prog else 'off'}: {sec:.2f} s, "
                   f"{s['elements']} elements, {s['links']} links")
            del solver
    return {("with" if k else "without"): {
        "runs": len(v), "seconds": statistics.median(r["seconds"] for r in v),
        "seconds_all": [round(r["seconds"], 3) for r in v],
        "elements": v[0]["elements"], "links": v[0]["links"], "rays": v[0]["rays"],
        "avoided_by_progressive": v[0]["avoided_by_progressive"]} for k, v in out.items()}


def main():
    a = parse()
    bt.install_addon(a.zip)
    scene = bpy.context.scene
    scene.radiosity.preset = a.preset
    objs = bt.mesh_objects(scene)
    movers, ref_obj = bt.move_targets(scene)
    start = bt.save_start(movers)
    res = {"scene": os.path.splitext(os.path.basename(bpy.data.filepath))[0], "preset": a.preset,
           "paper_input_surfaces": scene.get("radiosity_input_surfaces"),
           "paper_objects": scene.get("radiosity_input_objects"),
           "move": {k: (list(v) if hasattr(v, "__len__") and not isinstance(v, str) else v)
                    for k, v in dict(scene["radiosity_move"]).items()},
           "runs": a.runs, "date": time.strftime("%Y-%m-%d %H:%M"),
           "blender": bpy.app.version_string}

    # 2. with / without 3.5 (native, same gathered input)
    res["native"] = native_solves(a.preset, a.runs)

    # 1 + 3. full bake, move, incremental, full of the moved scene
    moves = []
    for r in range(a.runs):
        bt.place(scene, movers, ref_obj, start, 0.0)
        full0, sec0 = bt.our_bake(scene, a.preset, full=True)
        bt.place(scene, movers, ref_obj, start, 1.0)
        inc, sec_inc = bt.our_bake(scene, a.preset, full=False)
        x_inc = bt.all_corners(objs, bt.ATTR_OURS)
        full1, sec1 = bt.our_bake(scene, a.preset, full=True)
        x_full = bt.all_corners(objs, bt.ATTR_OURS)
        moves.append({"full_before": pick(full0), "incremental": pick(inc),
                      "full_after": pick(full1), "nrmse_inc_vs_full": nrmse(x_inc, x_full),
                      "ratio": inc["seconds"] / full1["seconds"],
                      "ratio_native": inc["seconds_total"] / full1["seconds_total"]})
        bt.log(f"move run {r + 1}: full {full0['seconds']:.2f} s, incremental "
               f"{inc['seconds']:.2f} s (link update {inc['seconds_adjust']:.2f} s), full after "
               f"{full1['seconds']:.2f} s, ratio {moves[-1]['ratio']:.3f}, NRMSE "
               f"{moves[-1]['nrmse_inc_vs_full']:.4f} (mode {inc['mode']})")
    res["moves"] = moves

    # 4. drag
    if a.drag_steps > 0:
        dp = a.drag_preset or a.preset
        bt.place(scene, movers, ref_obj, start, 0.0)
        bt.our_bake(scene, dp, full=True)
        steps = []
        for k in range(1, a.drag_steps + 1):
            bt.place(scene, movers, ref_obj, start, k / a.drag_steps)
            st, _ = bt.our_bake(scene, dp, full=False)
            steps.append({"seconds": st["seconds"], "seconds_adjust": st["seconds_adjust"],
                          "mode": st["mode"], "recomputed": st["env_env_links_recomputed"],
                          "tested": st["env_env_links_tested"], "elements": st["elements"],
                          "links": st["links"]})
        x_drag = bt.all_corners(objs, bt.ATTR_OURS)
        full_end, _ = bt.our_bake(scene, dp, full=True)
        x_full = bt.all_corners(objs, bt.ATTR_OURS)
        med = statistics.median(s["seconds"] for s in steps)
        res["drag"] = {"steps": a.drag_steps, "preset": dp, "median_step_seconds": med,
                       "step_seconds": [round(s["seconds"], 3) for s in steps],
                       "modes": sorted(set(s["mode"] for s in steps)),
                       "median_adjust_seconds": statistics.median(s["seconds_adjust"] for s in steps),
                       "full_seconds": full_end["seconds"], "ratio": med / full_end["seconds"],
                       "nrmse_vs_full": nrmse(x_drag, x_full),
                       "elements_end": steps[-1]["elements"], "links_end": steps[-1]["links"],
                       "full_elements": full_end["elements"], "full_links": full_end["links"]}
        bt.log(f"drag {a.drag_steps} steps: median step {med:.2f} s, full {full_end['seconds']:.2f}"
               f" s, ratio {res['drag']['ratio']:.3f}, NRMSE {res['drag']['nrmse_vs_full']:.4f}")
    with open(a.out, "w") as f:
        import json
        json.dump(res, f, indent=1)
    bt.result({"ok": True, "out": a.out})


main()
