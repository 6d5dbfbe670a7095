"""The error of a bake against a Cycles reference, per corner: the one definition every benchmark
and test uses (bench/accuracy_native.py, bench/tradeoff/*, tests/blender/scripts/*compare.py).

Pure numpy, no Blender: import it from plain python3 or from inside Blender (put this directory
on sys.path).

Which corners: every corner but emitters' (an emitter's own corners are trivially right). Corners
the reference reads as exactly 0 on all channels ("covered": a floor vertex under a box, a box's
bottom face on the floor, every ray from the vertex hits an object's inside) are counted: they
make contact shadows, and leaving them out flattered a furnished room from 59 % to 17 % rRMSE.
Their share of the error is reported separately so it cannot hide.

    floor  = 0.05 * mean(r)                      over the judged corners and channels (covered
                                                  corners included, so their zeros lower it)
    rel    = (x - r) / max(r, floor)             per corner and channel
    rRMSE  = sqrt(mean(rel^2))                   the headline: all judged corners
    NRMSE  = sqrt(mean((x - r)^2)) / sqrt(mean(r^2))
    covered_share      = sum(rel^2 over covered) / sum(rel^2)      (rRMSE's squared error)
    covered_share_abs  = sum((x-r)^2 over covered) / sum((x-r)^2)  (NRMSE's squared error)
    rrmse_uncovered    = sqrt(mean(rel^2 over uncovered corners)), the same floor: labelled as
                         such, never the headline
    rrmse_covered      = the same over covered corners (r = 0 there: |x| / floor)

With r = 0 the denominator is the floor, so a covered corner counts with a sane weight: an
estimate x there adds (x / (0.05 mean r))^2, as a dim uncovered corner would.

The reference's own noise. A reference made of k >= 2 independent Cycles bakes (different seeds,
n_j samples each, N = sum n_j) stores per corner the variance of its weighted mean,
var = sum_j n_j (x_j - m)^2 / ((k - 1) N) (unbiased). Our bake is independent of that noise, so
in expectation error^2 = true error^2 + noise^2 with
    noise_rRMSE^2 = mean(var / max(r, floor)^2),  noise_NRMSE^2 = mean(var) / mean(r^2),
and the figure with the reference's noise removed in quadrature is sqrt(max(0, e^2 - noise^2)).
"""
import json

import numpy as np

FLOOR_FRACTION = 0.05


def covered_mask(ref):
    """Corners the reference reads as exactly 0 on every channel."""
    return ~np.any(np.asarray(ref) > 0, axis=1)


def _rms(a):
    return float(np.sqrt(np.mean(a))) if a.size else float("nan")


def corner_error(x, ref, emitter=None, ref_var=None, mask=None, floor=None):
    """Error of x (C,3) against ref (C,3) over every corner but emitters' (bool (C,), or None).

    mask (bool (C,), optional): restrict to these corners as well (one object, a group of
    surfaces); floor: the denominator's floor to use (pass the whole scene's, scene_floor, so a
    group's squared errors add up to the scene's; default: 0.05 mean r over the corners
    judged here). ref_var (C,3), optional: the reference's per-corner noise variance
    (reference_noise_var); adds the reference-noise figures and the noise-removed ones.
    Returns a dict of floats and counts (see the module docstring)."""
    x = np.asarray(x, dtype=np.float64)
    r = np.asarray(ref, dtype=np.float64)
    if x.shape != r.shape:
        raise ValueError(f"shapes differ: ours {x.shape}, reference {r.shape}")
    judged = np.ones(len(r), bool) if emitter is None else ~np.asarray(emitter, bool)
    if mask is not None:
        judged &= np.asarray(mask, bool)
    cov_all = covered_mask(r)
    xs, rs = x[judged], r[judged]
    cov = cov_all[judged]
    out = {"corners": int(len(r)), "judged": int(judged.sum()), "covered": int(cov.sum()),
           "emitter": int(0 if emitter is None else np.asarray(emitter, bool).sum())}
    if not len(rs):
        return out
    if floor is None:
        floor = FLOOR_FRACTION * rs.mean()
    den = np.maximum(rs, floor) if floor > 0 else np.where(rs > 0, rs, 1.0)
    rel2 = ((xs - rs) / den) ** 2
    abs2 = (xs - rs) ** 2
    ms_r = float(np.mean(rs ** 2))
    out.update({
        "floor": float(floor),
        "rrmse": _rms(rel2),
        "nrmse": float(np.sqrt(np.mean(abs2) / ms_r)) if ms_r > 0 else float("nan"),
        "mean_ratio": float(xs.mean() / rs.mean()) if rs.mean() > 0 else float("nan"),
        "rel_p50": float(np.percentile(np.sqrt(rel2), 50)),
        "rel_p90": float(np.percentile(np.sqrt(rel2), 90)),
        "covered_share": float(rel2[cov].sum() / rel2.sum()) if rel2.sum() > 0 else 0.0,
        "covered_share_abs": float(abs2[cov].sum() / abs2.sum()) if abs2.sum() > 0 else 0.0,
        "rrmse_uncovered": _rms(rel2[~cov]),
        "nrmse_uncovered": (float(np.sqrt(np.mean(abs2[~cov]) / np.mean(rs[~cov] ** 2)))
                            if (~cov).any() else float("nan")),
        "rrmse_covered": _rms(rel2[cov]),
    })
    if ref_var is not None:
        v = np.asarray(ref_var, dtype=np.float64)[judged]
        n_rel2 = float(np.mean(v / den ** 2))
        n_abs2 = float(np.mean(v) / ms_r) if ms_r > 0 else float("nan")
        n_rel2_unc = float(np.mean((v / den ** 2)[~cov])) if (~cov).any() else float("nan")
        out.update({
            "ref_noise_rrmse": float(np.sqrt(n_rel2)),
            "ref_noise_nrmse": float(np.sqrt(n_abs2)),
            "ref_noise_rrmse_uncovered": float(np.sqrt(n_rel2_unc)),
            "rrmse_denoised": float(np.sqrt(max(0.0, out["rrmse"] ** 2 - n_rel2))),
            "nrmse_denoised": float(np.sqrt(max(0.0, out["nrmse"] ** 2 - n_abs2))),
            "rrmse_uncovered_denoised": float(np.sqrt(max(0.0, out["rrmse_uncovered"] ** 2
                                                          - n_rel2_unc))),
        })
    return out


def per_object(x, ref, names, counts, emitter=None, floor=None,
               keys=("rrmse", "nrmse", "covered", "covered_share"), skip=()):
    """{name: error of that object's corners (the `keys` of corner_error) with its and the
    reference's mean corner, "ours_mean" / "ref_mean"} for objects whose corners lie one after
    another in x and ref (counts, in names' order); objects named in `skip` are left out. Pass
    the scene's floor (scene_floor) so the objects' squared errors add up to the scene's."""
    x = np.asarray(x, dtype=np.float64)
    r = np.asarray(ref, dtype=np.float64)
    out, start = {}, 0
    for name, n in zip(names, counts):
        if name not in skip:
            m = np.zeros(len(r), bool)
            m[start:start + n] = True
            e = corner_error(x, r, emitter=emitter, mask=m, floor=floor)
            out[name] = {**{k: e[k] for k in keys if k in e},
                         "ours_mean": x[start:start + n].mean(axis=0).tolist(),
                         "ref_mean": r[start:start + n].mean(axis=0).tolist()}
        start += n
    return out


def scene_floor(ref, emitter=None):
    """The floor of the whole scene's rRMSE: 0.05 mean r over every corner but emitters'."""
    r = np.asarray(ref, dtype=np.float64)
    judged = np.ones(len(r), bool) if emitter is None else ~np.asarray(emitter, bool)
    return float(FLOOR_FRACTION * r[judged].mean())


# --- references made of independent parts ------------------------------------------------------

def combine_parts(parts, spp):
    """Weighted mean of k independent bakes (parts (k,C,3), spp (k,)) and the per-corner
    variance of that mean (None when k < 2): see the module docstring."""
    parts = np.asarray(parts, dtype=np.float64)
    n = np.asarray(spp, dtype=np.float64)
    total = n.sum()
    mean = np.tensordot(n, parts, axes=1) / total
    if len(n) < 2:
        return mean, None
    ss = np.tensordot(n, (parts - mean) ** 2, axes=1)
    return mean, ss / ((len(n) - 1) * total)


def load_reference(path):
    """(corners (C,3) float64, per-corner noise variance (C,3) or None, meta dict) of a cached
    reference (bench/tradeoff/refs/SCENE_cycles.npz; see bench/tradeoff/README.md)."""
    z = np.load(path, allow_pickle=False)
    meta = json.loads(str(z["meta"]))
    var = z["corners_var"].astype(np.float64) if "corners_var" in z.files else None
    return z["corners"].astype(np.float64), var, meta


def fmt_row(e, keys=("rrmse", "rrmse_uncovered", "covered_share", "nrmse")):
    """Short text of corner_error's main figures (for logs)."""
    names = {"rrmse": "rRMSE", "rrmse_uncovered": "rRMSE uncovered-only",
             "covered_share": "covered share", "nrmse": "NRMSE",
             "rrmse_denoised": "rRMSE ref-noise removed", "ref_noise_rrmse": "ref noise rRMSE"}
    return ", ".join(f"{names.get(k, k)} {e[k]:.4f}" for k in keys if k in e)
