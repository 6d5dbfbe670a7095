"""The zip is also a valid Blender 4.2+ extension (relative imports, __package__)."""
import pytest


def test_installs_as_extension(run_blender):
    r = run_blender("extension.py")
    if "skip" in r:
        pytest.skip(r["skip"])
    assert r["installed"] == ["FINISHED"]
    assert "bl_ext.user_default.radiosity" in r["modules"], r["modules"]
    assert r["native"] == ["bl_ext.user_default.radiosity.radiosity_native"], r["native"]
    assert r["ok"] and r["max_rel_err"] < 1e-3
