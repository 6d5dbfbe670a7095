"""Incremental re-bake through the native dynamic API, in real Blender (both flavours)."""
import os

import pytest

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.dirname(os.path.dirname(HERE))
BOX_ROOM = os.path.join(REPO, "example_blends", "box_room.blend")
# NRMSE incremental vs full: the goal, 0.005. Measured: the box room's stored move
# (the paper's scene and move) 0.0048, its light change 0.0029, the live move after it 0.0043;
# the small open diffuse scene 0.0016 / 0.0000 / 0.0005.
TOL = 0.005


def _check(r):
    assert all(r["ok"]), r["_log"]
    if r["first"].get("fake"):
        pytest.skip("numeric checks need the real native module")
    for key in ("move", "light", "live"):
        st = r[key]
        assert st["mode"] == "incremental", (key, st)
        assert st["cached"] is False
        for k in ("env_env_links_recomputed", "env_env_links_tested", "links_created"):
            assert k in st, (key, k)
    assert r["move"]["moved"] == 1 and r["light"]["emission_changed"] == 1
    for key in ("move_full", "light_full"):
        assert r[key]["mode"] == "full" and r[key]["full_reason"] == "full bake requested"
    assert r["move_changed"] > 0.005          # the move did change the lighting
    assert r["live_runs"] == 1 and not r["live_errors"], r
    assert r["live"]["live"] is True
    print(f"\n[{r['_flavour']}] NRMSE move {r['move_nrmse']:.4f} light {r['light_nrmse']:.4f} "
          f"live {r['live_nrmse']:.4f}; worst object {r['move_worst']}; seconds inc "
          f"{r['move']['seconds']:.2f} full {r['move_full']['seconds']:.2f}")
    assert r["move_nrmse"] < TOL, r["move_nrmse"]
    assert r["light_nrmse"] < TOL, r["light_nrmse"]
    assert r["live_nrmse"] < TOL, r["live_nrmse"]


def test_incremental_diffuse_scene(run_blender):
    _check(run_blender("incremental.py", "--scene", "diffuse"))


def test_incremental_box_room(run_blender):
    if not os.path.exists(BOX_ROOM):
        pytest.skip("no example_blends/box_room.blend")
    _check(run_blender("incremental.py", "--scene", "blend", blend=BOX_ROOM))
