"""Only written meshes are gathered (core.scene_data.ObjectInput.output): collection instances
and an area light light the scene without final-gather points, and the written colours are
those of a bake that gathers everything."""
import pytest


def test_instances_and_area_lights_are_not_gathered(run_blender):
    r = run_blender("output_flag.py")
    assert r["ok"], (r["err"], r["_log"])
    if r["fake"]:
        pytest.skip("the stand-in native module has no final gather")
    st, st_all = r["stats"], r["stats_all"]
    assert st["instances"] == 2, st
    written = sum(r["corners"].values())
    # Floor, Light, Box: every corner of theirs and no other is gathered.
    assert st["gather_corners"] == written, (st["gather_corners"], r["corners"])
    # Everything gathered: two crates (6 x 4 quads of 4 corners each) and the area light's
    # quad besides.
    assert st_all["gather_corners"] == written + 2 * 96 + 4, st_all["gather_corners"]
    assert st["gather_points"] < st_all["gather_points"]
    assert st["gather_rays"] < st_all["gather_rays"]
    for name, same in r["same"].items():
        assert same, name
        assert r["lit"][name] > 0, name
