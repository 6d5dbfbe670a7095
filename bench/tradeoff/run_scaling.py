"""Scaling of the full bake with scene size: one command (wraps build/bench/bench_scaling).

    python3 bench/tradeoff/run_scaling.py [--quick] [--preset DRAFT] [--timeout 600] [--max-mb 12000]
        [--sizes 1000,4000,...] [--out-dir bench/results]

bench_scaling runs every size in a fresh process (peak memory per size) and prints the table and
the log-log exponents; this wrapper saves its output as OUT/scaling.md (with the command), the
raw rows as OUT/scaling_data.jsonl and plots OUT/scaling.png (matplotlib). --quick: 1k and 4k
triangles only, output to a temporary directory unless --out-dir is given (CI smoke run).
"""
import argparse
import json
import os
import subprocess
import sys
import tempfile
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


def main():
    p = argparse.ArgumentParser(prog="run_scaling.py")
    p.add_argument("--quick", action="store_true")
    p.add_argument("--preset", default="DRAFT")
    p.add_argument("--timeout", type=int, default=600)
    p.add_argument("--max-mb", type=int, default=12000)
    p.add_argument("--sizes")
    p.add_argument("--families")
    p.add_argument("--exe", default=os.path.join(REPO, "build", "bench", "bench_scaling"))
    p.add_argument("--out-dir")
    a = p.parse_args()
    out_dir = a.out_dir or (tempfile.mkdtemp(prefix="scaling-quick-") if a.quick
                            else os.path.join(REPO, "bench", "results"))
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
    md = ["# Scaling of the full bake with scene size (issue 5)", "",
          "Command (from the repository root, after the build):", "", f"    {command.strip()}",
          "", f"{time.strftime('%Y-%m-%d %H:%M')}; machine at the start: {before}; at the end: "
          f"{bt_run.machine()}; {total:.0f} s in all.", "",
          "![scaling](scaling.png)", "", "```", out.strip(), "```", ""]
    with open(os.path.join(out_dir, "scaling.md"), "w") as f:
        f.write("\n".join(md) + "\n")
    print(f"results in {out_dir}/scaling.md")


main()
