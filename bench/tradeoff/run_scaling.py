"""Scaling of the full bake with scene size: one command (wraps build/bench/bench_scaling).

    python3 bench/tradeoff/run_scaling.py [--quick] [--preset DRAFT] [--timeout 600] [--max-mb 12000]
        [--sizes 1000,4000,...] [--out-dir bench/results]

bench_scaling runs every size in a fresh process (peak memory per size) and prints the table and
the log-log exponents; this wrapper saves its output as OUT/scaling.md (with the command), the
raw rows as OUT/scaling_data.jsonl and plots OUT/scaling.png (matplotlib). --quick: 1k and 2k
triangles only, output to a temporary directory unless --out-dir is given (CI smoke run).
"""
import json
import os
import subprocess
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.dirname(os.path.dirname(HERE))
sys.path.insert(0, HERE)
import bt_run  # noqa: E402


def plot(rows, path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fams = sorted(set(r["family"] for r in rows))
    fig, axes = plt.subplots(1, 3, figsize=(15, 4.5))
    for fam, m in zip(fams, "os^"):
        rs = sorted((r for r in rows if r["family"] == fam), key=lambda r: r["triangles"])
        n = [r["triangles"] for r in rs]
        axes[0].plot(n, [r["seconds"] for r in rs], m + "-", label=f"{fam}: wall s")
        axes[0].plot(n, [r["cpu_seconds"] for r in rs], m + ":", label=f"{fam}: CPU s")
        axes[1].plot(n, [r["vmhwm_kb"] / 1024 for r in rs], m + "-", label=fam)
        axes[2].plot(n, [r["elements"] for r in rs], m + "-", label=f"{fam}: elements")
        axes[2].plot(n, [r["links"] for r in rs], m + "--", label=f"{fam}: links")
    for ax, name in zip(axes, ("full bake, s", "peak memory (VmHWM), MB", "count")):
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_xlabel("input triangles")
        ax.set_ylabel(name)
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=8)
    fig.suptitle("bench_scaling: synthetic rooms, full bake (2 cores)")
    fig.tight_layout()
    fig.savefig(path, dpi=90)
    plt.close(fig)


def slope(xs, ys):
    import numpy as np
    if len(xs) < 2:
        return float("nan")
    return float(np.polyfit(np.log(xs), np.log(ys), 1)[0])


def table(rows):
    """The same table and fits bench_scaling prints, from rows of several runs."""
    out = ["| family | triangles | objects | elements | links | cluster links | rays | bake s (wall) "
           "| CPU s | peak MB (VmHWM) | history links | capped |", "|---|---|---|---|---|---|---|---|---|---|---|---|"]
    fams = sorted(set(r["family"] for r in rows))
    for fam in fams:
        for r in sorted((r for r in rows if r["family"] == fam), key=lambda r: r["triangles"]):
            out.append(f"| {fam} | {r['triangles']:,} | {r['objects']} | {r['elements']:,} | "
                       f"{r['links']:,} | {r['cluster_links']:,} | {r['rays']:,} | "
                       f"{r['seconds']:.2f} | {r['cpu_seconds']:.2f} | {r['vmhwm_kb'] / 1024:.0f} | "
                       f"{r['history_links']:,} | {'yes' if r['capped'] else 'no'} |")
    out += ["", "Log-log least-squares exponents (y ~ n^b, n = input triangles; \"uncapped\": only "
            "the sizes where no cap stopped refinement — a capped run hit the minimum element "
            "area or a count cap):", "",
            "| family | sizes | wall time | CPU time | peak memory | elements | links | rays |",
            "|---|---|---|---|---|---|---|---|"]
    for fam in fams:
        for which in ("uncapped", "all"):
            rs = [r for r in rows if r["family"] == fam and (which == "all" or not r["capped"])]
            n = [r["triangles"] for r in rs]
            f = [slope(n, [r[k] for r in rs]) for k in ("seconds", "cpu_seconds", "vmhwm_kb",
                                                         "elements", "links", "rays")]
            out.append(f"| {fam} ({which}) | {len(rs)} | " + " | ".join(f"{v:.2f}" for v in f) + " |")
    return "\n".join(out)


def main():
    p = bt_run.driver_parser("run_scaling.py")
    p.add_argument("--preset", default="DRAFT")
    p.add_argument("--timeout", type=int, default=600)
    p.add_argument("--max-mb", type=int, default=12000)
    p.add_argument("--sizes")
    p.add_argument("--families")
    p.add_argument("--exe", default=os.path.join(REPO, "build", "bench", "bench_scaling"))
    p.add_argument("--from-jsonl", nargs="*",
                   help="no run: merge the rows of earlier runs' JSONL files (later rows of the "
                        "same family and size win), refit, rewrite the table and plot")
    a = p.parse_args()
    if a.from_jsonl:
        out_dir = a.out_dir or os.path.join(REPO, "bench", "results")
        merged = {}
        for path in a.from_jsonl:
            for l in open(path):
                if l.strip():
                    r = json.loads(l)
                    merged[(r["family"], r["target"])] = r
        rows = list(merged.values())
        with open(os.path.join(out_dir, "scaling_data.jsonl"), "w") as f:
            for r in sorted(rows, key=lambda r: (r["family"], r["triangles"])):
                f.write(json.dumps(r) + "\n")
        plot(rows, os.path.join(out_dir, "scaling.png"))
        print(table(rows))
        return
    out_dir = bt_run.results_dir(a.out_dir, a.quick, "scaling")
    os.makedirs(out_dir, exist_ok=True)
    jsonl = os.path.join(out_dir, "scaling_data.jsonl")
    cmd = [a.exe, "--preset", a.preset, "--timeout", str(a.timeout), "--max-mb", str(a.max_mb),
           "--jsonl", jsonl]
    if a.quick:
        cmd.append("--quick")
    if a.sizes:
        cmd += ["--sizes", a.sizes]
    if a.families:
        cmd += ["--families", a.families]
    before = bt_run.machine()
    t0 = time.perf_counter()
    out = []
    with subprocess.Popen(cmd, stdout=subprocess.PIPE, text=True, bufsize=1) as proc:
        for line in proc.stdout:      # streamed: progress shows as each size finishes
            print(line, end="", flush=True)
            out.append(line)
    if proc.returncode != 0:
        raise SystemExit(f"bench_scaling failed (exit {proc.returncode})")
    out = "".join(out)
    total = time.perf_counter() - t0
    rows = [json.loads(l) for l in open(jsonl) if l.strip()]
    if rows:
        plot(rows, os.path.join(out_dir, "scaling.png"))
    command = "python3 bench/tradeoff/run_scaling.py " + " ".join(sys.argv[1:])
    md = ["# Scaling of the full bake with scene size", "",
          "Command (from the repository root, after the build):", "", f"    {command.strip()}",
          "", f"{time.strftime('%Y-%m-%d %H:%M')}; machine at the start: {before}; at the end: "
          f"{bt_run.machine()}; {total:.0f} s in all.", "",
          "![scaling](scaling.png)", "", "```", out.strip(), "```", ""]
    with open(os.path.join(out_dir, "scaling.md"), "w") as f:
        f.write("\n".join(md) + "\n")
    print(f"results in {out_dir}/scaling.md")


main()
