"""The live drag's preview (core.preview) on the kept solution: which objects moved, the
native preview's patches put into the last bake's colours, nothing of the kept solution touched."""
import numpy as np
import pytest

from radiosity.core import job, presets, preview, session

import scenes_np


# Each test starts and ends with no kept solution (conftest.py).
pytestmark = pytest.mark.usefixtures("no_kept_solutions")


def _bake(native, si):
    j = job.SolveJob(native, si, presets.make_settings(native, "DRAFT"),
                     presets.settings_key("DRAFT", 0.05), cache_key="scene")
    return j.prepare().run()


def _matrix(dx, dy):
    m = np.eye(4)
    m[:3, 3] = (1.2 + dx, 1.4 + dy, 0.0)
    return m


def test_preview_follows_a_moved_box_and_leaves_the_kept_solution(native):
    _bake(native, scenes_np.room())
    entry = session.kept("scene")
    if not hasattr(entry.solver, "preview"):
        assert not preview.available(entry)     # the stand-in module has no preview
        return
    assert preview.available(entry)
    kept = [np.array(r, copy=True) for r in entry.radiance]
    # Where the solution has it: nothing moved, nothing to show.
    assert preview.moves(entry, {"box": _matrix(0, 0)}) == {}
    assert preview.radiance(entry, {"box": _matrix(0, 0)}) == ({}, {})
    # Scaled: not a rigid move, left to the update (which re-bakes the object).
    scaled = _matrix(0.5, 0) @ np.diag([1.5, 1, 1, 1])
    assert preview.moves(entry, {"box": scaled}) == {}
    moved = _matrix(0.8, 0.6)
    mv = preview.moves(entry, {"box": moved, "wall0": np.eye(4)})
    assert list(mv) == [entry.object_ids["box"]]
    changed, counts = preview.radiance(entry, {"box": moved})
    assert "box" in changed and counts["rays"] > 0 and counts["points"] > 0
    for name, rad in changed.items():
        i = entry.names.index(name)
        assert rad.shape == kept[i].shape and rad.dtype == np.float32
        assert np.isfinite(rad).all() and (rad >= 0).all()
        assert not np.array_equal(rad, kept[i])
    # The kept solution is as it was: the preview neither wrote its colours nor moved it.
    for a, b in zip(entry.radiance, kept):
        assert np.array_equal(a, b)
    assert entry.matrices["box"] is not None and np.allclose(entry.matrices["box"], _matrix(0, 0))
    # The preview is far closer to the update of the new place than the colours before.
    full = _bake(native, scenes_np.room((0.8, 0.6)))
    assert full.mode == "incremental"
    truth = np.concatenate([r for r in full.radiance()])
    shown = np.concatenate([changed.get(n, kept[i]) for i, n in enumerate(entry.names)])
    before = np.concatenate(kept)

    def nrmse(x):
        return float(np.sqrt(np.mean((x - truth) ** 2)) / np.sqrt(np.mean(truth ** 2)))
    assert nrmse(shown) < 0.6 * nrmse(before), (nrmse(shown), nrmse(before))
    # While an update owns the solver there is no preview.
    entry.in_use = True
    assert not preview.available(entry)
    entry.in_use = False


def test_rgba_for_maps_written_corners_and_skips_objects_without_a_target():
    class Entry:
        outputs = {"a": {"target": "mesh", "corner_perm": None, "corner_map": [2, 0]},
                   "b": {"target": None, "corner_perm": None, "corner_map": None}}
        names = ["a", "b"]
        radiance = [np.arange(9, dtype=np.float32).reshape(3, 3), np.zeros((1, 3), np.float32)]
    rad = Entry.radiance[0]
    rgba = preview.rgba_for(Entry, "a", rad).reshape(-1, 4)
    assert np.array_equal(rgba[:, :3], rad[[2, 0]]) and (rgba[:, 3] == 1).all()
    assert preview.rgba_for(Entry, "b", Entry.radiance[1]) is None
    assert preview.base_radiance(Entry, "b") is Entry.radiance[1]
    assert preview.base_radiance(Entry, "c") is None
