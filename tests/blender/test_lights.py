"""Blender lights and world against converged Cycles, incremental light changes, adaptive mesh.

References: tests/blender/data/lights_<case>_<v3|v4>.npy, 8192 spp, made by
tests/blender/scripts/make_light_references.py (v3 with Debian's Blender 3.4, v4 with PyPI bpy
5.0; the area and spot units differ between them, see addon/radiosity/core/lights.py). A flavour
whose Blender generation has no reference skips.
"""
import os

import pytest

DATA = os.path.join(os.path.dirname(__file__), "data")
CASES = ("area_square", "area_rect", "area_disk", "area_ellipse", "point", "spot", "sun", "world")
TOL = 0.03           # NRMSE at HIGH (the bar)
TOL_INCREMENTAL = 0.005


@pytest.mark.parametrize("case", CASES)
def test_light_matches_cycles(run_blender, case):
    r = run_blender("lights_compare.py", "--case", case, "--data", DATA, "--preset", "HIGH")
    assert r["ok"], r["_log"]
    if r["fake"]:
        pytest.skip("stand-in native module: no accuracy to check")
    if not r["have_ref"]:
        pytest.skip(f"no {r['tag']} reference for {case}")
    assert r["shape_ok"]
    e = r["all"]     # bench/corner_metric.py: every corner, covered ones (under the box) included
    print(f"\n[{r['_flavour']} {r['tag']}] {case}: NRMSE {e['nrmse']:.4f}, rRMSE {e['rrmse']:.4f} "
          f"(uncovered-only {e['rrmse_uncovered']:.4f}, covered share "
          f"{100 * e['covered_share']:.1f} % over {e['covered']} corners); NRMSE "
          + " ".join(f"{k} {v['nrmse']:.4f}" for k, v in r["per_object"].items()))
    assert r["nrmse"] <= TOL, r["per_object"]


@pytest.mark.parametrize("case", ("point", "area_square"))
def test_light_change_is_incremental(run_blender, case):
    r = run_blender("lights_incremental.py", "--case", case, "--preset", "HIGH")
    assert all(r["ok"]), r["_log"]
    if r["fake"]:
        pytest.skip("stand-in native module")
    assert r["inc"]["mode"] == "incremental", r["inc"]
    assert r["full"]["mode"] == "full"
    if case == "point":
        assert r["inc"]["lights_changed"] == 1
    else:
        assert r["inc"]["emission_changed"] == 1
    print(f"\n[{r['_flavour']}] {case}: incremental vs full NRMSE {r['nrmse']:.4f} (the change "
          f"itself {r['changed']:.3f}); seconds inc {r['inc']['seconds']:.2f} full {r['full']['seconds']:.2f}")
    assert r["changed"] > 0.05           # the change did change the lighting
    # Goal: 0.5 % for both. Measured (3.4 and 5.0): area dimming 0.00 %, point-light move
    # 0.24 % (the rest at the box's foot, where the link refinement of an update and of a
    # full solve still differ a little; 0.68 % before the update judged a lit scene's first
    # links on the lamps' first bounce, as a full solve does).
    assert r["nrmse"] <= TOL_INCREMENTAL, r["nrmse"]


def test_adaptive_mesh(run_blender):
    r = run_blender("lights_adaptive.py", "--preset", "MEDIUM")
    assert r["ok"], r["_log"]
    if r["fake"]:
        pytest.skip("stand-in native module")
    for name, o in r["objects"].items():
        assert o["exists"] and o["original_loops_same"], (name, o)
        assert o["faces"] > o["input_faces"], (name, o)     # refined somewhere
        assert o["max_edge_share"] <= 2, (name, o)
        assert o["t_vertices"] == 0, (name, o)
        assert o["colour_worst_rel"] < 1e-5, (name, o)
        assert abs(o["area"] - o["input_area"]) < 1e-4 * o["input_area"], (name, o)
