"""(d) Bad input: clear reports, scene unchanged."""


def _errors(r):
    return [m for level, m in r["reports"] if level == "ERROR"]


def test_nan_vertex_is_an_error_naming_the_object(run_blender):
    r = run_blender("bad_input.py", "--case", "nan")
    assert not r["ok"]
    assert "Broken" in r["err"] and ("NaN" in r["err"] or "finite" in r["err"]), r["err"]
    assert not any(r["written"].values()), r["written"]     # nothing written anywhere
    assert r["stats_unchanged"]


def test_empty_scene_is_an_error(run_blender):
    r = run_blender("bad_input.py", "--case", "empty")
    assert not r["ok"] and "nothing to bake" in r["err"], r
    assert r["stats_unchanged"]


def test_only_unbakeable_objects_is_an_error(run_blender):
    r = run_blender("bad_input.py", "--case", "only_nonmesh")
    assert not r["ok"] and "nothing to bake" in r["err"], r


def test_zero_area_faces_are_skipped_not_fatal(run_blender):
    r = run_blender("bad_input.py", "--case", "zero_area")
    assert r["ok"], r["_log"]
    assert r["written"]["Degenerate"]
    lo, hi, alpha = r["values"]["Degenerate"]
    assert alpha and lo >= 0.0 and hi < 1e6


def test_no_emitter_bakes_black_with_warning(run_blender):
    r = run_blender("bad_input.py", "--case", "no_emitter")
    assert r["ok"], r["_log"]
    warnings = [m for level, m in r["reports"] if level == "WARNING"]
    assert any("emitter" in w for w in warnings), r["reports"]
    for name, (lo, hi, alpha) in r["values"].items():
        assert lo == 0.0 and hi == 0.0 and alpha, name
    assert r["stats"]["no_emitter"] is True
