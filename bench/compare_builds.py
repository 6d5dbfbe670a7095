#!/usr/bin/env python3
"""Before/after timing of two builds on a shared machine: runs the same benchmark of build A and
build B alternately (A, B, A, B, ...) so that both see the same load, and prints the median of
each figure and the median of the per-pair ratios B / A. Counts must agree between A and B (a
gather or speed change must not change the solution); they are printed so a difference shows.

    python3 bench/compare_builds.py --a /path/to/build-before --b build --pairs 5 static box_room 0.02
    python3 bench/compare_builds.py --a /path/to/build-before --b build --pairs 5 dynamic MEDIUM

static: bench_gather --runs 1 SCENE EPS (one row per pair).
dynamic: bench_dynamic --runs 1 --no-drag --preset PRESET.
update: bench/update_examples.py --runs 1 --preset PRESET SCENE.npz with each build's Python module
(build/native); the A build needs only its radiosity_native target.

    python3 bench/compare_builds.py --a /path/to/build-before --b build --pairs 7 update MEDIUM /tmp/box_room.npz
"""
import argparse
import os
import re
import statistics
import subprocess
import sys


def run(cmd):
    return subprocess.run(cmd, check=True, capture_output=True, text=True).stdout


def static_figures(build, scene, eps):
    out = run([os.path.join(build, "bench", "bench_gather"), "--runs", "1", scene, eps])
    row = next(l for l in out.splitlines() if l.startswith("| " + eps + " "))
    c = [x.strip() for x in row.strip("|").split("|")]
    return {
        "counts": "elements %s links %s rays %s sweeps %s" % (c[1], c[2], c[3], c[4]),
        "gather phase s": float(c[6]),
        "gather ns per link-sweep": float(c[7]),
        "sweeps ns per link-sweep": float(c[8]),
        "closure phase s": float(c[12]),
        "gather + closure s": float(c[6]) + float(c[12]),
        "total s": float(c[13]),
    }


def dynamic_figures(build, preset):
    out = run([os.path.join(build, "bench", "bench_dynamic"), "--runs", "1", "--no-drag", "--preset", preset])

    def cell(label):
        m = re.search(r"^\| " + re.escape(label) + r" \| ([^|]+) \|", out, re.M)
        return m.group(1).strip()

    def phase(block, name):
        m = re.search(block + r" phases.*?" + r" " + name + r" ([0-9.]+)", out)
        return float(m.group(1)) if m else 0.0

    def gathering(block):
        i = out.index(block + " phases")
        m = re.search(r"gather phase ([0-9.]+) ns, sweeps alone ([0-9.]+) ns", out[i:])
        return float(m.group(1)), float(m.group(2))

    fg, fs = gathering("full solve")
    ug, us = gathering("update")
    return {
        "counts": "elements %s links %s NRMSE %s" % (cell("elements"), cell("links"),
                                                    cell("NRMSE incremental vs full re-solve")),
        "full solve s": float(cell("full solve, s (with 3.5)")),
        "update s": float(cell("whole incremental update, s")),
        "full re-solve s": float(cell("full re-solve of the moved scene, s")),
        "update / full re-solve %": float(cell("update / full re-solve").rstrip(" %")),
        "full: gather + closure s": phase("full solve", "gather") + phase("full solve", "closure"),
        "full: gather ns per link-sweep": fg,
        "full: sweeps ns per link-sweep": fs,
        "update: gather + closure s": phase("update", "gather") + phase("update", "closure"),
        "update: gather ns per link-sweep": ug,
        "update: sweeps ns per link-sweep": us,
    }


def update_figures(build, preset, scene):
    script = os.path.join(os.path.dirname(os.path.abspath(__file__)), "update_examples.py")
    env = dict(os.environ, RADIOSITY_NATIVE_DIR=os.path.join(os.path.abspath(build), "native"))
    out = subprocess.run([sys.executable, script, "--runs", "1", "--preset", preset, scene], check=True,
                         capture_output=True, text=True, env=env).stdout
    m = re.search(r"full ([0-9.]+) s, update ([0-9.]+) s, ratio ([0-9.]+) %, NRMSE ([0-9.]+) %; (links .*)", out)
    return {
        "counts": "%s, NRMSE %s %%" % (m.group(5), m.group(4)),
        "full solve of the moved scene s": float(m.group(1)),
        "update s": float(m.group(2)),
        "update / full %": float(m.group(3)),
    }


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--a", required=True, help="build directory before the change")
    ap.add_argument("--b", required=True, help="build directory after the change")
    ap.add_argument("--pairs", type=int, default=5)
    ap.add_argument("what", choices=["static", "dynamic", "update"])
    ap.add_argument("args", nargs="+")
    a = ap.parse_args()
    fig = {
        "static": lambda b: static_figures(b, a.args[0], a.args[1]),
        "dynamic": lambda b: dynamic_figures(b, a.args[0]),
        "update": lambda b: update_figures(b, a.args[0], a.args[1]),
    }[a.what]
    rows = []
    for _ in range(a.pairs):
        rows.append((fig(a.a), fig(a.b)))
    counts_a = {r[0]["counts"] for r in rows}
    counts_b = {r[1]["counts"] for r in rows}
    print("%s %s, %d alternating pairs; A = %s, B = %s" % (a.what, " ".join(a.args), a.pairs, a.a, a.b))
    print("counts A: %s\ncounts B: %s%s" % (" / ".join(sorted(counts_a)), " / ".join(sorted(counts_b)),
                                             "" if counts_a == counts_b else "   <-- DIFFERENT"))
    print("\n| figure | A median | B median | median of B / A |\n|---|---|---|---|")
    for key in rows[0][0]:
        if key == "counts":
            continue
        va = [r[0][key] for r in rows]
        vb = [r[1][key] for r in rows]
        ratios = [y / x for x, y in zip(va, vb) if x > 0]
        print("| %s | %.4g | %.4g | %s |" % (key, statistics.median(va), statistics.median(vb),
                                             "%.2f" % statistics.median(ratios) if ratios else "-"))


if __name__ == "__main__":
    main()
