"""The paper's Table 2 on the example .blend scenes, with their stored moves: one command.

    python3 bench/tradeoff/run_table2.py [--quick] [--scenes box_room chair_room full_room]
        [--preset MEDIUM] [--runs 1] [--drag-steps 30] [--drag-preset DRAFT]
        [--zip build/radiosity.zip]
        [--out-dir bench/results] [--report-only]

Per scene Debian's Blender runs table2_scene.py (full bake; native full solves with and without
the 3.5 strategy; the stored move: incremental re-bake vs a full bake of the moved scene; a drag
of --drag-steps incremental steps); JSON in OUT/table2_data/, table in OUT/table2_examples.md.
Cheap to rerun (about 10 minutes at MEDIUM with DRAFT drags); --quick
(CI smoke run, no timing judged): the Cornell box only (it has a stored move too and bakes 4-5×
faster than the box room: ~25 s in all), DRAFT, a 3-step drag, output to a temporary directory
unless --out-dir is given.
"""
import argparse
import json
import os
import statistics
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.dirname(os.path.dirname(HERE))
sys.path.insert(0, HERE)
import bt_run  # noqa: E402

SCENES = ("box_room", "chair_room", "full_room")
# The paper's Table 2 (SGI O2), shared/paper and shared/NOTES.md.
PAPER = {
    "box_room": {"surfaces": 19, "objects": 2, "elements": 5723, "links": 4785, "obj_env": 294,
                 "env_env": 4476, "time": 32.6, "time_no35": 35.1, "recomputed": "987 (22.05 %)",
                 "update": 2.64},
    "chair_room": {"surfaces": 73, "objects": 1, "elements": 5641, "links": 7086, "obj_env": 708,
                   "env_env": 4233, "time": 38.01, "time_no35": 41.23,
                   "recomputed": "2556 (60.38 %)", "update": 9.99},
    "full_room": {"surfaces": 203, "objects": 4, "elements": 7943, "links": 22726,
                  "obj_env": 3636, "env_env": 16945, "time": 182.07, "time_no35": 221.33,
                  "recomputed": "1639 (9.67 %)", "update": 22.55},
}


def med(xs):
    return statistics.median(xs)


def update_mode(inc):
    """The add-on's mode, and whether the native update fell back to a full solve (it does when
    a move changes a closed pocket, adjust.cpp; the add-on still says "incremental" then, its
    only trace a solver warning): no env–env link tested and no link update at all."""
    mode = inc.get("mode") or "?"
    if inc.get("full_reason"):
        return f"{mode} ({inc['full_reason']})"
    if mode == "incremental" and not inc.get("env_env_links_tested") and not inc.get("seconds_adjust"):
        return "incremental requested, solved in full by the native update (no env–env link tested)"
    return mode


def before_move(key):
    """A cell of our column: `key` of the full bake before the first move, as 12,345."""
    return lambda d: f"{d['moves'][0]['full_before'][key]:,}"


def report(data, out_dir, command):
    rows = [
        ("input surfaces (paper-style / polygons)",
         lambda d: f"{d['paper_input_surfaces']} / {d['moves'][0]['full_before']['input_surfaces']:,}",
         lambda p: p["surfaces"]),
        ("objects", lambda d: f"{d['paper_objects']} ({d['moves'][0]['full_before']['objects']} "
                              f"meshes)", lambda p: p["objects"]),
        ("elements", before_move("elements"), lambda p: f"{p['elements']:,}"),
        ("links (active)", before_move("links"), lambda p: f"{p['links']:,}"),
        ("cluster links", before_move("cluster_links"), lambda p: ""),
        ("obj–env links", before_move("obj_env_links"), lambda p: f"{p['obj_env']:,}"),
        ("env–env links", before_move("env_env_links"), lambda p: f"{p['env_env']:,}"),
        ("full bake, add-on operator, s", lambda d: f"{med(m['full_before']['seconds'] for m in d['moves']):.2f}",
         lambda p: ""),
        ("full solve with 3.5 (native), s", lambda d: f"{d['native']['with']['seconds']:.2f} "
                                                     f"({d['native']['with']['elements']:,} el., "
                                                     f"{d['native']['with']['links']:,} links)",
         lambda p: p["time"]),
        ("full solve without 3.5 (native), s", lambda d: f"{d['native']['without']['seconds']:.2f} "
                                                        f"({d['native']['without']['elements']:,} el., "
                                                        f"{d['native']['without']['links']:,} links)",
         lambda p: p["time_no35"] or "–"),
        ("refinements 3.5 avoided", lambda d: f"{d['native']['with']['avoided_by_progressive']:,}",
         lambda p: ""),
        ("env–env links tested / rejected / recomputed",
         lambda d: (lambda i: f"{i['env_env_links_tested']:,} / {i['env_env_links_rejected']:,} / "
                              f"{i['env_env_links_recomputed']:,} "
                              f"({100 * i['env_env_links_recomputed'] / max(1, i['env_env_links_tested']):.1f} % of tested; "
                              f"tested = every env–env link the move could touch, inactive ones included)"
                              + (f"; and {i['history_links_recomputed']:,} history links re-evaluated"
                                 if "history_links_recomputed" in i else ""))
         (d["moves"][0]["incremental"]), lambda p: ""),
        ("env–env links recomputed (÷ active env–env links before the move: the paper's %)",
         lambda d: (lambda i: f"{i['env_env_links_recomputed']:,} "
                              f"({100 * i['env_env_links_recomputed'] / max(1, d['moves'][0]['full_before']['env_env_links']):.1f} %)")
         (d["moves"][0]["incremental"]), lambda p: p["recomputed"]),
        ("link update (AdjustSystem), s",
         lambda d: f"{med(m['incremental']['seconds_adjust'] for m in d['moves']):.2f}",
         lambda p: p["update"]),
        ("whole incremental re-bake, s",
         lambda d: f"{med(m['incremental']['seconds'] for m in d['moves']):.2f}", lambda p: ""),
        ("full re-bake of the moved scene, s",
         lambda d: f"{med(m['full_after']['seconds'] for m in d['moves']):.2f}", lambda p: ""),
        ("update / full (operator; native solve only)",
         lambda d: f"{med(m['ratio'] for m in d['moves']):.3f}; "
                   f"{med(m['ratio_native'] for m in d['moves']):.3f}",
         lambda p: f"{p['update'] / p['time']:.3f} (link update / full)"),
        ("update mode", lambda d: "; ".join(sorted({update_mode(m["incremental"]) for m in d["moves"]})),
         lambda p: ""),
        ("NRMSE incremental vs full", lambda d: f"{med(m['nrmse_inc_vs_full'] for m in d['moves']):.4f}",
         lambda p: ""),
        ("drag: preset, steps, median step s / full s = ratio",
         lambda d: (f"{d['drag'].get('preset', d['preset'])}, {d['drag']['steps']}, "
                    f"{d['drag']['median_step_seconds']:.2f} / "
                    f"{d['drag']['full_seconds']:.2f} = {d['drag']['ratio']:.3f}") if "drag" in d else "–",
         lambda p: ""),
        ("drag: step modes", lambda d: ", ".join(d["drag"].get("modes", [])) if "drag" in d else "–",
         lambda p: ""),
        ("drag: NRMSE after the last step vs full",
         lambda d: f"{d['drag']['nrmse_vs_full']:.4f}" if "drag" in d else "–", lambda p: ""),
        ("drag: elements / links after the drag vs full",
         lambda d: (f"{d['drag']['elements_end']:,} / {d['drag']['links_end']:,} vs "
                    f"{d['drag']['full_elements']:,} / {d['drag']['full_links']:,}") if "drag" in d else "–",
         lambda p: ""),
    ]
    head = "| | " + " | ".join(f"{d['scene']} (ours, {d['preset']}) | paper" for d in data) + " |"
    lines = [head, "|---|" + "---|---|" * len(data)]
    for name, ours, paper in rows:
        cells = []
        for d in data:
            p = PAPER.get(d["scene"], {})
            try:
                o = ours(d)
            except (KeyError, TypeError, ZeroDivisionError) as exc:
                o = f"n/a ({exc})"
            cells += [o, str(paper(p)) if p else ""]
        lines.append(f"| {name} | " + " | ".join(cells) + " |")
    moves = "; ".join(f"{d['scene']}: {d['move']['object']} → {tuple(d['move']['location'])}, "
                      f"+{d['move'].get('rotation_z_deg', 0)}° about Z" for d in data)
    md = ["# Table 2 on the example scenes", "",
          "Command (from the repository root, after the build; one headless run, Debian's Blender "
          "3.4):", "", f"    {command.strip()}", "",
          f"{data[0]['date']}; commit measured: "
          f"{', '.join(sorted({d.get('commit', 'not recorded') for d in data}))}; "
          "machine after each scene: "
          f"{'; '.join(d['scene'] + ': ' + d.get('machine_after', 'not recorded') for d in data)}. "
          "Runs per measurement: "
          f"{data[0]['runs']} (medians); the drag is one run. Ratios of two single runs on a shared "
          "machine are good to about ±20 %; counts do not depend on load.", "",
          "Where each figure comes from: counts and the operator's seconds are the add-on's "
          "`last_stats` (`bpy.ops.radiosity.bake`, wall time of the whole operator: gather, solve, "
          "write). The add-on has no setting for the §3.5 strategy (`progressive_refinement`), so "
          "the with/without rows gather the scene with the add-on's own gather path "
          "(`radiosity.gather` → `core.scene_data.build_native_scene`) and time "
          "`radiosity_native.Solver.solve()` directly, interleaved. The move is the file's "
          "`scene[\"radiosity_move\"]` (" + moves + "); the incremental re-bake (`full=False`) "
          "starts from the full bake, the full re-bake (`full=True`) of the moved scene is its "
          "reference for the ratio and the NRMSE (all corners, emitters included). The drag "
          "splits the same move into equal steps, one incremental re-bake each, from a fresh full "
          "bake; its ratio is the median step over a full bake of the final placement. "
          "“Input surfaces” as in the paper count modelled planar surfaces "
          "(`scene[\"radiosity_input_surfaces\"]`); the solver sees the meshes' polygons. "
          "The paper's update/full is its link update over its full time.", "",
          "\n".join(lines), ""]
    with open(os.path.join(out_dir, "table2_examples.md"), "w") as f:
        f.write("\n".join(md) + "\n")


def main():
    p = argparse.ArgumentParser(prog="run_table2.py")
    p.add_argument("--quick", action="store_true")
    p.add_argument("--scenes", nargs="*")
    p.add_argument("--preset", default=None)
    p.add_argument("--runs", type=int, default=1)
    p.add_argument("--drag-steps", type=int, default=None)
    p.add_argument("--drag-preset", default=None)
    p.add_argument("--zip", default=os.path.join(REPO, "build", "radiosity.zip"))
    p.add_argument("--out-dir")
    p.add_argument("--report-only", action="store_true")
    a = p.parse_args()
    scenes = a.scenes or (["cornell_box"] if a.quick else list(SCENES))
    preset = a.preset or ("DRAFT" if a.quick else "MEDIUM")
    drag = a.drag_steps if a.drag_steps is not None else (3 if a.quick else 30)
    out_dir = bt_run.results_dir(a.out_dir, a.quick, "table2")
    data_dir = bt_run.data_dir(out_dir, "table2")
    command = "python3 bench/tradeoff/run_table2.py " + " ".join(sys.argv[1:])
    if not a.report_only:
        t0 = time.perf_counter()
        commit = bt_run.git_commit()
        for s in scenes:
            print(f"== {s} ({bt_run.machine()})", flush=True)
            bt_run.run(os.path.join(REPO, "example_blends", f"{s}.blend"), "table2_scene.py",
                       ["--zip", a.zip, "--out", os.path.join(data_dir, f"{s}.json"),
                        "--preset", preset, "--runs", a.runs, "--drag-steps", drag,
                        "--drag-preset", a.drag_preset or preset],
                       log_path=os.path.join(data_dir, f"{s}.log"))
            bt_run.stamp(os.path.join(data_dir, f"{s}.json"), commit=commit,
                         machine_after=bt_run.machine(), command=command)
        print(f"all scenes: {time.perf_counter() - t0:.0f} s", flush=True)
    data = [json.load(open(os.path.join(data_dir, f"{s}.json"))) for s in scenes
            if os.path.exists(os.path.join(data_dir, f"{s}.json"))]
    if not data:
        raise SystemExit(f"no results in {data_dir}: run without --report-only first")
    # The command that measured the data (a --report-only rerun only rewrites the table).
    report(data, out_dir, data[0].get("command", command))
    print(f"results in {out_dir}/table2_examples.md")


main()
