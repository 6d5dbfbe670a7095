"""Interactive Blender under Xvfb: modal bake with progress, undo restores, Esc cancels, and a
live re-bake driven by the real depsgraph handler + bpy.app.timers; the panel as seen in a
1600x1000 window."""
import pytest

from ui_window import run_ui_window  # noqa: F401  (fixture)


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


def test_panel_in_a_1600x1000_window(run_ui_window):
    """The panel in Blender 3.4's window under Xvfb (screenshots in the run's shots
    folder: the opened file, the panel after a bake, the tooltips, the restored shading)."""
    r = run_ui_window("ui_panel.py")
    assert "exception" not in r, r["exception"]
    assert "Traceback" not in r["_output"], r["_log"]
    # 17.5: box_room.blend opens looking through its camera.
    assert r["opened_view"] == "CAMERA" and r["camera"] == "Camera"
    # 17.4: the stats in plain words, polygons named as such.
    d = r["describe"]
    assert d["headline"].startswith("Bake: solved from scratch")
    assert d["details"][0].startswith("Why from scratch: no solution was kept")
    assert d["counts"][1][0] == "Polygons" and d["counts"][1][1] == 3992
    # Bake and Full each say what they do; the trash button is labelled and explained.
    assert "incrementally where it can" in r["tip_bake"]
    assert "solving from scratch" in r["tip_full"]
    assert r["clear_label"] == "Free Solver Memory" and "\n" not in r["clear_tip"]
    assert "baked colours stay" in r["clear_tip"]
    # Show Baked Colours shows the bake as it is (Flat), and the user can go back.
    assert r["shading_before"] == ["SOLID", "MATERIAL", "STUDIO"]
    assert r["shading_shown"] == ["SOLID", "VERTEX", "FLAT"] and r["panel_offers_back"]
    assert r["shading_restored"] == r["shading_before"] and r["panel_offers_show"]
