"""Gaps under objects: the floor under an object that does not touch it gets only the light that
comes in through the gap, and must read what Cycles reads there (no light leaking under a cube
lifted 1 mm, a slab 1 cm up; the dim light under a slab 15 cm up, as a real object and as a
collection instance).

Scenes: corner_scenes.py's gap_* cases, baked with the add-on in real Blender (each conftest
flavour) and compared with converged Cycles references in tests/blender/data
(tests/blender/scripts/make_corner_references.py --cases gap_cube,gap_slab,gap_slab_instance,
gap_slab_1cm: 16,384 spp as two halves). The floor's grid lines miss the objects' edges, so
floor quads straddle each footprint: half lit, half in the dark under it.

Metric over the floor corners strictly under the object: where Cycles reads about 0, our
largest value against the floor's mean; elsewhere rRMSE with each corner's error relative to
max(ref, 0.05 x the floor's mean), the reference's own noise removed (test_corner_exact.rrmse).
"""
import numpy as np
import pytest

from test_corner_exact import bake, label, reference, rrmse

DARK_TOL = 0.005                          # of the floor's mean, where Cycles reads ~0
SLAB_TOL = {"MEDIUM": 0.11, "HIGH": 0.05}  # rRMSE under the 15 cm slab, noise removed
SLAB_MEAN_TOL = {"MEDIUM": 0.07, "HIGH": 0.03}


def _under(r, d):
    half = r["info"]["half"]
    pos = d["pos"]
    return (d["object"] == 0) & (np.abs(pos[:, 0]) < half - 1e-6) & (np.abs(pos[:, 1]) < half - 1e-6)


@pytest.mark.parametrize("case", ["gap_cube", "gap_slab_1cm"])
def test_no_light_leaks_into_a_thin_gap(run_blender, case):
    """A cube 1 mm over the floor under a sky, a slab 1 cm over it beside a point light: Cycles
    reads (nearly) 0 under them; so must we, to within 0.5 % of the floor's mean. MEDIUM."""
    r, d = bake(run_blender, case, "MEDIUM")
    x = d["ours"]
    ref, noise, meta = reference(case, r["tag"], len(x))
    floor = d["object"] == 0
    under = _under(r, d)
    mean_floor = ref[floor].mean()
    worst = float(x[under].max() / mean_floor)
    e, n, e_clean = rrmse(x, ref, noise, floor)
    print(f"\n{label(r)} {case}: {int(under.sum())} floor corners under it, ours max / floor mean "
          f"{worst:.2e} (Cycles {ref[under].max() / mean_floor:.2e}; target < {DARK_TOL}); "
          f"floor rRMSE {e:.4f} (noise removed {e_clean:.4f})")
    assert under.sum() >= 64
    assert ref[under].max() < DARK_TOL * mean_floor   # the reference agrees: dark there
    assert worst < DARK_TOL


@pytest.mark.parametrize("case,preset", [("gap_slab", "MEDIUM"), ("gap_slab", "HIGH"),
                                         ("gap_slab_instance", "MEDIUM")])
def test_floor_under_a_floating_slab(run_blender, case, preset):
    """The floor under a slab 15 cm up reads 1-8 % of the lit floor's light, all of it through
    the gap; ours within SLAB_TOL rRMSE and SLAB_MEAN_TOL in the mean of Cycles' there. The
    light there is 1-8 % of the lit floor's, so it takes a threshold that follows the receiver's
    light down to 5 % of the scene's (threshold_floor 0.05; at 0.1: MEDIUM 13 %, HIGH 6.4 %)."""
    r, d = bake(run_blender, case, preset)
    x = d["ours"]
    ref, noise, meta = reference(case, r["tag"], len(x))
    under = _under(r, d)
    floor = d["object"] == 0
    # Relative to the floor's mean, as the scene metric: rrmse() floors by the set's own mean.
    m = ref[floor].mean()
    scale = np.maximum(ref[under], 0.05 * m)
    e = float(np.sqrt(np.mean(((x[under] - ref[under]) / scale) ** 2)))
    nz = float(np.sqrt(np.mean((noise[under] / scale) ** 2)))
    e_clean = float(np.sqrt(max(e * e - nz * nz, 0.0)))
    ratio = float(x[under].mean() / ref[under].mean())
    worst = float((np.abs(x[under] - ref[under]) / scale).max())
    print(f"\n{label(r)} {case}: {int(under.sum())} floor corners under the slab: rRMSE {e:.4f} "
          f"(ref noise {nz:.4f}, removed {e_clean:.4f}; target <= {SLAB_TOL[preset]}), mean ours/ref "
          f"{ratio:.3f}, worst corner {worst:.2f}; floor rRMSE {rrmse(x, ref, noise, floor)[2]:.4f}")
    assert under.sum() >= 200
    assert nz < SLAB_TOL[preset] / 2    # the reference is converged enough to judge by (1.6-1.9 %)
    assert e_clean <= SLAB_TOL[preset]
    assert abs(ratio - 1.0) <= SLAB_MEAN_TOL[preset]


CLOSED_MEAN_TOL = 0.005                   # per surface, ours / Cycles - 1


@pytest.mark.parametrize("preset", ["MEDIUM", "HIGH"])
def test_closed_box_surfaces_as_bright_as_cycles(run_blender, preset):
    """A closed box lit by a mesh lamp 1 mm under its gridded ceiling: nothing leaves it, so any
    light a solver makes or loses shows on every surface. Each surface's mean (all its corners)
    within 0.5 % of Cycles'; the reference's own noise in a surface mean is far below that."""
    r, d = bake(run_blender, "closed_box", preset)
    x = d["ours"]
    # Judged against Blender 5.x's Cycles in every flavour (the scene is diffuse and emission
    # only, baked the same in 3.4): 3.4's Cycles reads a mesh lamp seen at grazing angles too
    # dark (bench/accuracy_native.py), and the ceiling beside this lamp comes out 0.8 % darker
    # there than in 5.x.
    ref, noise, meta = reference("closed_box", "v4", len(x))
    ratios, noise_rel = {}, {}
    for k, name in enumerate(meta["objects"]):
        m = d["object"] == k
        if name in meta["emitters"]:
            continue
        ratios[name] = float(x[m].mean() / ref[m].mean())
        noise_rel[name] = float(np.sqrt(np.mean(noise[m] ** 2) / m.sum()) / ref[m].mean())
    e, n, e_clean = rrmse(x, ref, noise, ~d["emitter"])
    print(f"\n{label(r)} closed_box: ours/Cycles per surface "
          + ", ".join(f"{k} {v:.4f}" for k, v in ratios.items())
          + f"; rRMSE {e:.4f} (noise removed {e_clean:.4f})")
    assert max(noise_rel.values()) < CLOSED_MEAN_TOL / 5, noise_rel
    worst = max(abs(v - 1.0) for v in ratios.values())
    assert worst <= CLOSED_MEAN_TOL, ratios
