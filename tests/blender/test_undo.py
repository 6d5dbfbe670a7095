"""Undo. Headless Blender (`-b`, and the bpy module) has no undo stack: `bpy.ops.ed.undo()`
fails its poll there (checked on 3.4 and bpy 5.0), so the restore itself is checked in
test_ui.py (interactive Blender under Xvfb); headless we check the operator's undo flags."""
import pytest


def test_bake_registers_undo_and_undo_restores(run_blender):
    r = run_blender("undo.py")
    assert r["baked"], r["_log"]
    assert "UNDO" in r["bl_options"] and "REGISTER" in r["bl_options"]
    if "undo_error" in r:
        assert "poll() failed" in r["undo_error"], r["undo_error"]
        pytest.skip(f"{r['_flavour']}: no undo stack headless ({r['undo_error']})")
    assert not r["attr_after_undo"]
