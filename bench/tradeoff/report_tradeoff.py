"""Tables and plots of the trade-off runs (plain python3: numpy + matplotlib), from saved JSON.

    python3 bench/tradeoff/report_tradeoff.py --data bench/results/tradeoff_data \
        --out-dir bench/results --command "..." [--scenes ...]

Speed-up at equal error: Cycles' time at our error, read off Cycles' curve by linear
interpolation in log(error)-log(time) between its two neighbouring points (beyond its ends, the
nearest segment's line is extended: marked "extrap."), divided by our time. The errors compared
are rRMSE with the reference's own noise removed in quadrature (both sides) when the reference
has parts to measure it: raw errors flatten toward that noise as Cycles converges, so a segment
extended on raw errors would under-count the samples Cycles needs.
"""
import argparse
import json
import math
import os

import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import matplotlib.ticker  # noqa: E402
import numpy as np  # noqa: E402

import scenes as bt_scenes  # noqa: E402  (this directory: the references' file names)


def label(p):
    if p["kind"] == "cycles":
        return f"Cycles {p['spp']} spp"
    return p["preset"] if p["preset"] != "CUSTOM" else f"eps {p['eps']:g}"


def cycles_time_at(cyc, err, key, tkey="seconds"):
    """Cycles seconds at error `err` (log-log interpolation on its curve); (seconds, extrapolated)."""
    if any(c.get(tkey) is None or c[tkey] != c[tkey] for c in cyc):
        return float("nan"), False
    pts = sorted(((c[key], c[tkey]) for c in cyc), key=lambda t: -t[0])  # error falling
    le = np.log([e for e, _ in pts])
    lt = np.log([t for _, t in pts])
    x = math.log(err)
    if len(pts) < 2:
        return float("nan"), True
    for i in range(len(pts) - 1):
        if le[i] >= x >= le[i + 1]:
            f = (x - le[i]) / (le[i + 1] - le[i]) if le[i + 1] != le[i] else 0.0
            return math.exp(lt[i] + f * (lt[i + 1] - lt[i])), False
    i = 0 if x > le[0] else len(pts) - 2
    slope = (lt[i + 1] - lt[i]) / (le[i + 1] - le[i])
    return math.exp(lt[i] + slope * (x - le[i])), True


def speed_key(d):
    """The error the speed-ups compare: rRMSE with the reference's noise removed when every point
    has it (the reference's parts measured its noise), else raw rRMSE."""
    return ("rrmse_denoised" if all(p.get("rrmse_denoised") is not None for p in d["points"])
            else "rrmse")


def time_at(d, cyc, p, tkey="seconds"):
    """Cycles' tkey at point p's error (speed_key); (value, extrapolated). NaN when p's error is
    below what the reference resolves (noise removed to 0)."""
    key = speed_key(d)
    if not p[key] > 0 or any(not c[key] > 0 for c in cyc):
        return float("nan"), True
    return cycles_time_at(cyc, p[key], key, tkey)


def ref_file(d):
    """The cached reference's file name: the one made in the Blender generation that ran."""
    flavour = "bpy" if int(str(d["blender"]).split(".")[0]) >= 5 else "binary"
    return os.path.basename(bt_scenes.ref(d["scene"], flavour))


def ref_noise(d, cyc, key):
    """The reference's own noise: measured from its independent parts when it has them
    (corner_metric: the per-corner variance of their mean; stored per point as ref_noise_*),
    else estimated from Cycles' curve: Cycles' error at N spp is sqrt(s^2/N + s^2/Nref), so the
    reference's part is err_N * sqrt(N / (N + Nref)), taken from the largest N."""
    measured = [p.get("ref_noise_" + key) for p in d["points"] if p.get("ref_noise_" + key) is not None]
    if measured:
        return measured[0]
    if not cyc:
        return float("nan")
    best = max(cyc, key=lambda c: c["spp"])
    n, nref = best["spp"], d["reference"]["samples"]
    return best[key] * math.sqrt(n / (n + nref))


def noise_measured(d):
    return any(p.get("ref_noise_rrmse") is not None for p in d["points"])


def g(p, key):
    """A figure of a point, NaN when the JSON predates it."""
    v = p.get(key)
    return float("nan") if v is None else v


def pct(v):
    return "–" if v != v else f"{100 * v:.1f} %"


def plot(d, path):
    ours = [p for p in d["points"] if p["kind"] == "ours"]
    cyc = sorted((p for p in d["points"] if p["kind"] == "cycles"), key=lambda p: p["spp"])
    # CPU seconds when every point has them (load-robust on a shared machine), else wall seconds.
    tk = "cpu_seconds" if all(p.get("cpu_seconds") == p.get("cpu_seconds") and p.get("cpu_seconds")
                              for p in d["points"]) else "seconds"
    fig, axes = plt.subplots(1, 2, figsize=(12, 5))
    for ax, key, name in ((axes[0], "rrmse", "rRMSE (per-corner relative)"),
                          (axes[1], "nrmse", "NRMSE")):
        if cyc:
            ax.plot([c[tk] for c in cyc], [c[key] for c in cyc], "o-", color="tab:blue",
                    label=f"Cycles ({cyc[0]['spp']}…{cyc[-1]['spp']} spp)")
            for c in cyc:
                ax.annotate(f"{c['spp']}", (c[tk], c[key]), textcoords="offset points",
                            xytext=(4, 4), fontsize=8, color="tab:blue")
        custom = sorted((p for p in ours if p["preset"] == "CUSTOM"), key=lambda p: -p["eps"])
        if custom:
            ax.plot([p[tk] for p in custom], [p[key] for p in custom], "s--",
                    color="tab:orange", label="ours, CUSTOM ε")
            for p in custom:
                ax.annotate(f"ε={p['eps']:g}", (p[tk], p[key]), textcoords="offset points",
                            xytext=(4, -10), fontsize=8, color="tab:orange")
        for p, m in zip([p for p in ours if p["preset"] != "CUSTOM"], "^DP"):
            ax.plot([p[tk]], [p[key]], m, color="tab:red", markersize=9)
            ax.annotate(p["preset"], (p[tk], p[key]), textcoords="offset points",
                        xytext=(6, 2), fontsize=9, color="tab:red", weight="bold")
        noise = ref_noise(d, cyc, key)
        if noise == noise:
            ax.axhline(noise, color="gray", ls=":", lw=1,
                       label=f"reference's own noise ({d['reference']['samples']} spp"
                             f"{', from its parts' if noise_measured(d) else ', est.'})")
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.xaxis.set_minor_formatter(matplotlib.ticker.NullFormatter())
        ax.yaxis.set_minor_formatter(matplotlib.ticker.NullFormatter())
        ax.set_xlabel("CPU seconds (process, all threads; median)" if tk == "cpu_seconds"
                      else "wall seconds (2 cores, median)")
        ax.set_ylabel(name)
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=8)
    fig.suptitle(f"{d['scene']}: error vs time against a {d['reference']['samples']}-spp Cycles "
                 f"bake ({d['judged_corners']} corners judged, {d['covered_corners']} of them covered)")
    fig.tight_layout()
    fig.savefig(path, dpi=90)
    plt.close(fig)


def cpu(p):
    c = p.get("cpu_seconds")
    return "–" if c is None or c != c else f"{c:.1f}"


def scene_table(d):
    cyc = [p for p in d["points"] if p["kind"] == "cycles"]
    lines = ["| config | runs | seconds (median) | CPU s | elements | links | rays | rRMSE (all) | "
             "rRMSE, ref. noise removed | covered share | rRMSE uncovered-only | NRMSE | "
             "mean ours/ref | rel. err p50 / p90 | Cycles s at our rRMSE (noise removed) | "
             "speed-up (rRMSE, noise removed) | speed-up (raw NRMSE) | "
             "speed-up in CPU s (rRMSE, noise removed) |",
             "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
    for p in d["points"]:
        if p["kind"] == "ours":
            st = p["stats"]
            tc, ext = time_at(d, cyc, p)
            tn, extn = cycles_time_at(cyc, p["nrmse"], "nrmse")
            tcpu, extc = time_at(d, cyc, p, "cpu_seconds")
            our_cpu = p.get("cpu_seconds") or float("nan")
            lines.append(
                f"| {label(p)} | {p['runs']} | {p['seconds']:.2f} | {cpu(p)} | {st['elements']:,} | "
                f"{st['links']:,} | {st['rays']:,} | {p['rrmse']:.4f} | {g(p, 'rrmse_denoised'):.4f} | "
                f"{pct(g(p, 'covered_share'))} | {g(p, 'rrmse_uncovered'):.4f} | {p['nrmse']:.4f} | "
                f"{p['mean_ratio']:.3f} | {p['rel_p50']:.3f} / {p['rel_p90']:.3f} | {tc:.2f}{' (extrap.)' if ext else ''} | "
                f"{tc / p['seconds']:.2f}×{' (extrap.)' if ext else ''} | "
                f"{tn / p['seconds']:.2f}×{' (extrap.)' if extn else ''} | "
                f"{tcpu / our_cpu:.2f}×{' (extrap.)' if extc else ''} |")
        else:
            lines.append(f"| {label(p)} | {p['runs']} | {p['seconds']:.2f} | {cpu(p)} | | | | "
                         f"{p['rrmse']:.4f} | {g(p, 'rrmse_denoised'):.4f} | "
                         f"{pct(g(p, 'covered_share'))} | {g(p, 'rrmse_uncovered'):.4f} | "
                         f"{p['nrmse']:.4f} | {p['mean_ratio']:.3f} | "
                         f"{p['rel_p50']:.3f} / {p['rel_p90']:.3f} | | | | |")
    return "\n".join(lines)


def per_object_table(d):
    ours = [p for p in d["points"] if p["kind"] == "ours"]
    names = d["objects"]
    lines = ["| config | " + " | ".join(names) + " |", "|---|" + "---|" * len(names)]
    for p in ours + [p for p in d["points"] if p["kind"] == "cycles"]:
        po = p.get("per_object", {})
        cells = [f"{po[n]['rrmse']:.3f} ({po[n]['mean_ratio']:.3f})" if n in po else "–"
                 for n in names]
        lines.append(f"| {label(p)} | " + " | ".join(cells) + " |")
    return "\n".join(lines)


def worst_table(p):
    lines = ["| object | polygon | corner position | ours RGB | reference RGB | rel. error |",
             "|---|---|---|---|---|---|"]
    for w in p["worst"]:
        lines.append(f"| {w['object']} | {w['polygon']} | {tuple(w['position'])} | "
                     f"{tuple(w['ours'])} | {tuple(w['ref'])} | {w['rel_err']:.2f} |")
    return "\n".join(lines)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--data", required=True)
    ap.add_argument("--out-dir", required=True)
    ap.add_argument("--command", default="")
    ap.add_argument("--scenes", nargs="*")
    a = ap.parse_args()
    files = sorted(f for f in os.listdir(a.data) if f.endswith(".json"))
    order = {s: i for i, s in enumerate(a.scenes or [])}
    data = [json.load(open(os.path.join(a.data, f))) for f in files]
    data.sort(key=lambda d: order.get(d["scene"], 99))
    blenders = sorted({str(d["blender"]) for d in data})
    md = ["# Speed vs accuracy: our bake against Cycles on the example scenes", "",
          "Command (from the repository root, after the build; one headless run, Blender "
          f"{', '.join(blenders)}: ours and Cycles in the same process):", "",
          f"    {a.command.strip()}", "",
          "What it does: per scene, a converged Cycles COMBINED bake to corner colours is the "
          "reference (non-adaptive, denoising off, 64 diffuse/max bounces, clamping 0; the "
          "spp-weighted mean of independent bakes with seeds 1, 2, …, whose spread gives the "
          "reference's own noise; cached in `bench/tradeoff/refs/SCENE_cycles5.npz` (made in "
          "Blender 5.x; `SCENE_cycles.npz`: 3.4, whose Cycles reads mesh lamps seen at grazing "
          "angles too dark, bench/results/reference_bias.md) with its "
          "settings, its parts and the .blend's sha256, so reruns reuse it; "
          "`bench/tradeoff/run_refs.py` makes them). Then, round-robin over the repetitions so the shared "
          "machine's slow phases hit everything alike: our `bpy.ops.radiosity.bake(full=True)` "
          "at each preset and CUSTOM ε (CUSTOM = MEDIUM with that ε), and Cycles at the sample "
          "counts in each scene's rows (seeds 101, 102, …: never the reference's). Seconds are wall time of the "
          "operator call (ours: gather, solve, write; Cycles: sync, BVH, bake, write), medians of "
          "the runs counted in `runs` (a configuration whose first run took more than "
          "`once_above` s ran once). Errors (`bench/corner_metric.py`) over every corner but "
          "emitters', those the reference reads as exactly 0 (covered by an object: the floor "
          "under a box, a box's bottom face) included; rRMSE = √mean(((x−r)/max(r, 0.05·mean r))²) "
          "(main; mean r over the same corners, zeros included, so at r = 0 the denominator is that "
          "floor), NRMSE = RMS(x−r)/RMS(r); *covered share* = the covered corners' part of rRMSE's "
          "squared error; *rRMSE uncovered-only* = the same over the uncovered corners alone "
          "(what older tables called rRMSE, up to the floor); *ref. noise removed* = "
          "√max(0, rRMSE² − n²), n the reference's own noise measured from its independent parts. "
          "Cycles' errors are medians over its seeds. \"Speed-up\" is Cycles' time at our error (log–log interpolation "
          "on its curve) over ours, both errors with the reference's noise removed (raw errors "
          "flatten toward that noise as Cycles converges; NRMSE's column compares raw NRMSE); \"extrap.\" means our error lies outside Cycles' measured range "
          "and the nearest segment was extended (Cycles error ∝ spp^-½, so this is a fair guess). "
          "The reference is itself noisy: its own noise (per-corner variance of the mean of its "
          "independent parts; for a reference of one bake, Cycles' error at its largest N × "
          "√(N/(N+N_ref))) is given per scene; errors near it cannot be resolved.", ""]
    summary = ["| scene | preset | seconds (wall) | CPU s | elements | rRMSE (all) | rRMSE, ref. noise "
               "removed | covered share | rRMSE uncovered-only | NRMSE | Cycles spp at "
               "that rRMSE (noise removed) | speed-up vs Cycles at equal rRMSE, noise removed "
               "(wall; CPU) |",
               "|---|---|---|---|---|---|---|---|---|---|---|---|"]
    by_preset = {}  # preset -> per scene (rRMSE, NRMSE, CPU s, CPU speed-up, CPU s / MEDIUM's)
    for d in data:
        cyc = [p for p in d["points"] if p["kind"] == "cycles"]
        png = f"tradeoff_{d['scene']}.png"
        plot(d, os.path.join(a.out_dir, png))
        ref = d["reference"]
        parts = ref.get("parts") or [{"samples": ref["samples"], "seed": ref.get("seed")}]
        md += [f"## {d['scene']}", "",
               f"{d['date']}, Blender {d['blender']}, commit {d.get('commit', 'not recorded')}; "
               f"machine after the run: {d.get('machine_after', 'not recorded')}. "
               f"{d['corners']:,} corners: "
               f"{d['emitter_corners']:,} emitter, {d['covered_corners']:,} covered, "
               f"{d['judged_corners']:,} judged (covered included). Reference: {ref['samples']} spp "
               f"({' + '.join(str(q['samples']) for q in parts)}, seeds "
               f"{', '.join(str(q.get('seed')) for q in parts)}), {ref['seconds']:.0f} s of Cycles "
               f"when made ({ref.get('made', '?')}), cached `{ref_file(d)}`. Its own noise "
               f"({'from its parts' if noise_measured(d) else 'estimated from Cycles' + chr(39) + ' curve'}): rRMSE "
               f"{ref_noise(d, cyc, 'rrmse'):.4f}, NRMSE {ref_noise(d, cyc, 'nrmse'):.4f}.", "",
               f"![{d['scene']}]({png})", "", scene_table(d), "",
               "Timing of every run (s): " + "; ".join(
                   f"{label(p)}: {', '.join(f'{s:.2f}' for s in p['seconds_all'])}"
                   for p in d["points"]), "",
               "Per object: rRMSE (mean ours/ref):", "", per_object_table(d), ""]
        finest = min((p for p in d["points"] if p["kind"] == "ours"), key=lambda p: p["rrmse"])
        md += [f"Worst corners of our most accurate bake ({label(finest)}):", "",
               worst_table(finest), ""]
        for p in d["points"]:
            if p["kind"] == "ours" and p["preset"] != "CUSTOM":
                tc, ext = time_at(d, cyc, p)
                tcpu, _ = time_at(d, cyc, p, "cpu_seconds")
                our_cpu = p.get("cpu_seconds") or float("nan")
                spp, exts = time_at(d, cyc, p, "spp")
                summary.append(f"| {d['scene']} | {p['preset']} | {p['seconds']:.2f} | {cpu(p)} | "
                               f"{p['stats']['elements']:,} | {p['rrmse']:.3f} | "
                               f"{g(p, 'rrmse_denoised'):.3f} | {pct(g(p, 'covered_share'))} | "
                               f"{g(p, 'rrmse_uncovered'):.3f} | "
                               f"{p['nrmse']:.3f} | ≈ {spp:.0f}{' (extrap.)' if exts else ''} | "
                               f"{tc / p['seconds']:.2f}×; {tcpu / our_cpu:.2f}×"
                               f"{' (extrap.)' if ext else ''} |")
                medium = [q for q in d["points"] if q["kind"] == "ours" and q["preset"] == "MEDIUM"]
                rel = our_cpu / (medium[0].get("cpu_seconds") or float("nan")) if medium else float("nan")
                by_preset.setdefault(p["preset"], []).append(
                    (p["rrmse"], p["nrmse"], our_cpu, tcpu / our_cpu, rel, spp,
                     g(p, "rrmse_uncovered"), g(p, "covered_share")))
    def span(vals, fmt):
        vals = [v for v in vals if v == v]
        if not vals:
            return "–"
        lo, hi = min(vals), max(vals)
        return fmt.format(lo) if fmt.format(lo) == fmt.format(hi) else f"{fmt.format(lo)}–{fmt.format(hi)}"

    overall = ["| preset | scenes | rRMSE to expect (all corners) | rRMSE uncovered-only | covered share | "
               "NRMSE to expect | CPU s | CPU s ÷ MEDIUM's | "
               "Cycles spp at that rRMSE (noise removed) | speed-up vs Cycles at equal rRMSE, noise "
               "removed (CPU) |",
               "|---|---|---|---|---|---|---|---|---|---|"]
    for preset in ("DRAFT", "MEDIUM", "HIGH"):
        r = by_preset.get(preset)
        if r:
            overall.append(f"| {preset} | {len(r)} | {span([x[0] for x in r], '{:.2f}')} | "
                           f"{span([x[6] for x in r], '{:.2f}')} | "
                           f"{span([100 * x[7] for x in r], '{:.0f} %')} | "
                           f"{span([x[1] for x in r], '{:.2f}')} | {span([x[2] for x in r], '{:.1f}')} | "
                           f"{span([x[4] for x in r], '{:.1f}')} | {span([x[5] for x in r], '{:.0f}')} | "
                           f"{span([x[3] for x in r], '{:.2f}')}× |")
    md += ["## Presets: what each costs and what error to expect", "",
           "Over the scenes above (ranges: smallest–largest; spp and speed-ups read off Cycles' "
           "curve, some extrapolated: see the per-scene rows):", "", "\n".join(overall), "",
           "Per scene:", "", "\n".join(summary), ""]
    with open(os.path.join(a.out_dir, "tradeoff.md"), "w") as f:
        f.write("\n".join(md) + "\n")


if __name__ == "__main__":
    main()
