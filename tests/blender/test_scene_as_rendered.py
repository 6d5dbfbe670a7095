"""The scene as Blender renders it (modifiers, instances), against a converged Cycles bake of the
same scene.

References: tests/blender/data/rendered_<scene>_cycles.npy (+ .json: samples, Blender), made by
tests/blender/scripts/make_rendered_reference.py (the command is in its docstring) from
tests/blender/scripts/scenes_rendered.py. Error: bench/corner_metric.py's rRMSE over every compared
corner (the written objects; the emitter is not compared; instances have no corners of their own).

Three kinds of check:
- the acceptance target (HIGH as shipped within 5 % rRMSE of Cycles; 2 % once the corner-exact
  output is in): with the final gather on in the presets, subsurf 0.92 %, instances 1.45 % (3.4;
  2.1 % before the gather's deep-penumbra rays, final_gather.cpp). With the old leaf-average output (gather_rays = 0) they measured 8.2 % and 11.6 %:
  that was the corner output's error, not the geometry's;
- the add-on's own share, which must hold now: with the native final gather (every corner
  evaluated at its point and normal, as Cycles does) each object a modifier changed matches
  Cycles corner by corner, so the evaluated corners map back to the original ones as Cycles
  maps them; instances give the same bake as the same meshes made real objects;
- the bake leaves the scene as it was but for our colour attribute, and its stats count
  objects and instances.
"""
import os

import pytest

DATA = os.path.join(os.path.dirname(__file__), "data")
# The acceptance bound once the corner-exact output is in (the final gather;
# 5 % before it): subsurf 0.92 %, instances 1.45 % measured.
RRMSE_BOUND = 0.02
# Measured at HIGH with the leaf-average output (gather_rays = 0; Blender 3.4, bpy 5.0 and 5.2
# alike), for the regression bounds below (a bit above each figure).
MEASURED = {"subsurf": 0.082, "instances": 0.116}


# Scenes whose Cycles bake differs between Blender 3.x and 5.x (Bevel's face order: see
# tests/blender/scripts/make_rendered_reference.py): a reference per generation.
PER_VERSION = {"modifiers"}


def _run(run_blender, scene, *extra):
    ref = os.path.join(DATA, f"rendered_{scene}_cycles{'_{v}' if scene in PER_VERSION else ''}"
                             f".npy")
    r = run_blender("rendered_compare.py", "--scene", scene, "--ref", ref, "--preset", "HIGH",
                    *extra)
    assert r["ok"], r["_log"]
    # The bake writes our colour attribute on the written meshes and nothing else anywhere:
    # the temporary original-index attributes are gone, the modifiers and objects untouched.
    for mesh, added in r["added_attributes"].items():
        assert added in ([], ["Radiosity"]), (mesh, added)
    assert not any(r["removed_attributes"].values()), r["removed_attributes"]
    assert r["modifiers_unchanged"] and r["objects_unchanged"]
    assert all(r["written"]), r["written"]
    if r["fake"]:
        pytest.skip("stand-in native module: no accuracy to check")
    assert r["shape_ok"]
    e = r["all"]
    print(f"\n[{r['_flavour']}] {scene} {' '.join(extra)}: rRMSE {e['rrmse']:.4f}, NRMSE "
          f"{e['nrmse']:.4f}; " + " ".join(f"{k} {v['rrmse']:.4f}"
                                          for k, v in r["per_object"].items()))
    return r


def test_subdivided_cube(run_blender):
    r = _run(run_blender, "subsurf")
    st = r["stats"]
    assert st["scene_objects"] == 3 and st["instances"] == 0, st     # Floor, Light, Cube
    assert st["written_objects"] == 3 and "unwritten_objects" not in st, st
    assert not any(level == "WARNING" for level, _ in r["reports"]), r["reports"]
    assert r["all"]["rrmse"] <= MEASURED["subsurf"] + 0.02, r["per_object"]


def test_instances_and_array(run_blender):
    r = _run(run_blender, "instances", "--realize", "1")
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
    # The same meshes as real objects: the same light on the floor and the rail. (Measured
    # 0.5 % rRMSE: the instances sit in clusters of their own, so the hierarchy differs.)
    assert r["realized"] == 5 and r["realized_stats"]["instances"] == 0, r["realized_stats"]
    assert r["instanced_vs_realized"]["rrmse"] <= 0.02, r["instanced_vs_realized"]
    assert r["all"]["rrmse"] <= MEASURED["instances"] + 0.02, r["per_object"]


@pytest.mark.parametrize("scene, bounds", [
    # Measured: Cube 0.6 %; Beveled 1.9 % (3.4) / 2.3 % (5.0, 5.2 against their own
    # reference), Mirrored 0.9 %, Shell 0.2 % / 0.03 %.
    ("subsurf", {"Cube": 0.02}),
    ("modifiers", {"Beveled": 0.03, "Mirrored": 0.02, "Shell": 0.02}),
])
def test_modified_corners_map_back_as_in_cycles(run_blender, scene, bounds):
    r = _run(run_blender, scene, "--gather-rays", "1024")
    assert not any(level == "WARNING" for level, _ in r["reports"]), r["reports"]
    for name, bound in bounds.items():
        assert r["per_object"][name]["rrmse"] <= bound, (name, r["per_object"])


def test_subdivided_cube_within_acceptance(run_blender):
    r = _run(run_blender, "subsurf")
    assert r["all"]["rrmse"] <= RRMSE_BOUND, r["per_object"]


def test_instances_and_array_within_acceptance(run_blender):
    r = _run(run_blender, "instances")
    assert r["all"]["rrmse"] <= RRMSE_BOUND, r["per_object"]


def test_instances_update_incrementally(run_blender):
    """Moving an Empty moves its instances (an incremental move of each, live too); one more
    geometry-nodes point adds an instance incrementally."""
    r = run_blender("rendered_incremental.py")
    assert all(r["ok"]), r["_log"]
    if r["fake"]:
        pytest.skip("numeric checks need the real native module")
    assert r["move"]["mode"] == "incremental" and r["move"]["moved"] == 2, r["move"]
    assert r["live_runs"] == 1 and r["live"]["mode"] == "incremental" \
        and r["live"]["moved"] == 2, r["live"]
    assert r["add"]["mode"] == "incremental" and r["add"]["added"] == 1 \
        and r["add"]["instances"] == 6, r["add"]
    assert r["move_changed"] > 0.05        # the move did change the light
    print(f"\n[{r['_flavour']}] NRMSE incremental vs full: move {r['move_nrmse']:.4f}, live "
          f"{r['live_nrmse']:.4f}, add {r['add_nrmse']:.4f}")
    # Measured (MEDIUM): move 0.033, live 0.023, add 0.029. The native update's own accuracy
    # on this scene, not the instances': moving the Rail, a real object, the same way measures
    # 0.028 / 0.042 / 0.023.
    for key in ("move_nrmse", "live_nrmse", "add_nrmse"):
        assert r[key] < 0.05, (key, r[key])


def test_every_kind_of_instance_takes_part(run_blender):
    r = run_blender("instance_kinds.py")
    assert r["ok"], r["_log"]
    st = r["stats"]
    # 6 particles (the emitter plate hidden by "Show Instancer: Render" off), 4 vertex
    # instances, the linked collection's box (its render-disabled box and the Empty hidden in
    # render give nothing); the text's own surface is no instance.
    assert st["instancers"] == {"Emitter": 6, "Verts": 4, "LibInstance": 1}, st
    assert st["instances"] == 11, st
    # Light, Floor, Label, VertChild (a vertex instancer's child still renders at its place).
    assert st["scene_objects"] == 4, st
    assert st["objects"] == 15, st
    assert r["floor_written"] and r["library_file"]
