"""A mouse drag in a viewport that draws slowly, then Ctrl+Z, through the window's own events
(interactive Blender under Xvfb): each frame of the drag takes --draw seconds more, so its
steps come about a second apart, slower than Live's pause. Every step shows a preview, the
update waits for the drag to stop, and undo gives back the earlier bake's colours at once,
from what is kept, without solving."""
from ui_window import run_ui_window  # noqa: F401  (fixture)

STEPS = 10


def test_slow_drag_previews_every_step_and_undo_restores_without_solving(run_ui_window):
    r = run_ui_window("ui_drag_undo.py", "--steps", str(STEPS), "--draw", "0.5")
    assert "exception" not in r, r["exception"]
    assert "Traceback" not in r["_output"], r["_log"]
    steps = r["steps"]
    print({k: v for k, v in r.items() if not k.startswith("_") and k != "steps"})
    assert all(s["moved"] for s in steps), steps
    # Slower than the pause (0.3 s): the case where an update used to start mid-drag.
    assert sorted(s["seconds"] for s in steps)[len(steps) // 2] > 0.5, steps
    # No update took the solver during the drag, so no step went without its preview (each
    # shows before the next move, or the next move's shows its place).
    assert not any(s["job"] for s in steps), steps
    assert r["previews_during_drag"] >= STEPS - 1, r["previews_during_drag"]
    # The last preview is close to the update at the same place and shows no black where the
    # update has light, but for a few corners at the foot of the box's sides (dark by the
    # floor in the bake, lit from below once the drag lifted it): 12 of 15,734.
    assert r["preview_vs_update"] < 0.02, r["preview_vs_update"]
    assert r["preview_black"] <= 0.002 * r["preview_lit"], (r["preview_black"], r.get("preview_black_by_object"))
    # One update once the drag stopped, and it changed the colours.
    assert r["live_runs_for_drag"] == 1, r["live_runs_for_drag"]
    assert r["drag_vs_C0"] > 0.01, r["drag_vs_C0"]
    # Ctrl+Z: the box back and the first bake's colours, by the next look (a timer tick).
    a = r["after_undo"]
    assert a["location_back"] and a["vs_C0"] < 1e-6, a
    # ... and nothing solved or previewed after it.
    later = r["later"]
    assert later["live_runs"] == 0 and not later["job"], later
    assert later["vs_C0"] < 1e-6 and later["stale"] is None, later
