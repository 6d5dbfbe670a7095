"""Issue 18, parts 1 and 2: the scene as Blender renders it (modifiers, instances), at HIGH,
against a converged Cycles bake of the same scene.

References: tests/blender/data/rendered_<scene>_cycles.npy (+ .json: samples, Blender), made by
scripts/make_rendered_reference.py (the command is in its docstring) from
scripts/scenes_rendered.py. Error: bench/corner_metric.py's rRMSE over every compared corner
(written objects only; the emitter is not compared; instances have no corners of their own).
"""
import os

import pytest

DATA = os.path.join(os.path.dirname(__file__), "data")
# Issue 18's acceptance bound before the corner-exact issue lands.
RRMSE_BOUND = 0.05


def _run(run_blender, scene):
    ref = os.path.join(DATA, f"rendered_{scene}_cycles.npy")
    r = run_blender("rendered_compare.py", "--scene", scene, "--ref", ref, "--preset", "HIGH")
    assert r["ok"], r["_log"]
    # The bake writes our colour attribute on the written meshes and nothing else anywhere.
    for mesh, added in r["added_attributes"].items():
        assert added in ([], ["Radiosity"]), (mesh, added)
    assert not any(r["removed_attributes"].values()), r["removed_attributes"]
    assert r["modifiers_unchanged"] and r["objects_unchanged"]
    assert all(r["written"]), r["written"]
    if r["fake"]:
        pytest.skip("stand-in native module: no accuracy to check")
    assert r["shape_ok"]
    e = r["all"]
    print(f"\n[{r['_flavour']}] {scene}: rRMSE {e['rrmse']:.4f}, NRMSE {e['nrmse']:.4f}; "
          + " ".join(f"{k} {v['rrmse']:.4f}" for k, v in r["per_object"].items()))
    return r


def test_subdivided_cube_matches_cycles(run_blender):
    r = _run(run_blender, "subsurf")
    st = r["stats"]
    assert st["scene_objects"] == 3 and st["instances"] == 0, st     # Floor, Light, Cube
    assert not any("topology" in m for _, m in r["reports"]), r["reports"]
    assert r["all"]["rrmse"] <= RRMSE_BOUND, r["per_object"]


def test_instances_and_array_match_cycles(run_blender):
    r = _run(run_blender, "instances")
    st = r["stats"]
    # Floor, Light, Rail (arrayed) are objects of the view layer; the Empty instances Crate and
    # Pebble, the geometry nodes three pebbles: 5 instances, occluders and reflectors only.
    assert st["scene_objects"] == 3, st
    assert st["instances"] == 5, st
    assert st["instancers"] == {"CrateInstance": 2, "Scatter": 3}, st
    assert st["occluder_only"] == ["CrateInstance", "Scatter"], st
    assert st["objects"] == 8, st
    said = [m for level, m in r["reports"] if level == "WARNING" and "instance" in m]
    assert len(said) == 1, r["reports"]
    assert r["all"]["rrmse"] <= RRMSE_BOUND, r["per_object"]
