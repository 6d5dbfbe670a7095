"""Interactive Blender under Xvfb: modal bake with progress, undo restores, Esc cancels, and a
live re-bake driven by the real depsgraph handler + bpy.app.timers."""
import pytest


def test_modal_bake_undo_and_escape(run_blender_ui):
    r = run_blender_ui("ui_modal.py")
    assert "exception" not in r, r["exception"]
    assert r["invoke"] == ["RUNNING_MODAL"]
    assert not r["attr_right_after_invoke"]          # nothing written before the job ends
    assert r["modal_done"] and r["stats_after_modal"]["mode"] == "full"
    assert r["undo"] == ["FINISHED"]
    assert not r["attr_after_undo"], "undo did not remove the baked attribute"
    assert r["stats_after_undo"] == ""                # last_stats restored too
    assert r["invoke2"] == ["RUNNING_MODAL"]
    assert any("cancelled" in m for _, m in r["reports_after_cancel"]), r["reports_after_cancel"]
    assert not r["attr_after_cancel"]                 # Esc: nothing written
    assert "live_timeout" not in r, "the live timer never re-baked after a move"
    assert r["live_runs"] >= 1, r
    # The live re-bake is the native incremental update (equal to a full bake within its
    # accuracy only).
    assert r["live_stats"]["mode"] == "incremental", r["live_stats"]
    assert r["live_floor_nrmse"] < 0.05, r["live_floor_nrmse"]
