"""(e) live re-bake after a move, driven synchronously with radiosity.pump()."""


def test_live_rebake_equals_full_bake(run_blender):
    r = run_blender("live.py")
    assert r["ok"], r["_log"]
    assert not r["pending_after_bake"], "our own colour write was taken for a move"
    assert r["pending_after_move"]
    assert r["runs"] == 1 and not r["live_errors"], r
    assert r["live_stats"]["cached"] is False
    assert r["changed_from_first"] > 1e-4        # the move changed the lighting
    assert r["max_abs_diff"] <= 1e-5, r["max_abs_diff"]
    assert not r["pending_live_off"] and r["runs_live_off"] == 0
