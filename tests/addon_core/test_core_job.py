"""SolveJob with a native module (stand-in and, if built, the real one)."""
import numpy as np
import pytest

from radiosity.core import job, presets, session

import scenes_np


def _job(native, si, preset="DRAFT", key="scene"):
    return job.SolveJob(native, si, presets.make_settings(native, preset),
                        presets.settings_key(preset, 0.05), cache_key=key)


# Each test starts and ends with no kept solution (conftest.py).
pytestmark = pytest.mark.usefixtures("no_kept_solutions")


def test_furnace_sync(native):
    j = _job(native, scenes_np.furnace(2)).prepare().run()
    for obj, rgba in j.rgba():
        c = rgba.reshape(-1, 4)
        assert np.allclose(c[:, :3], 2.0, rtol=1e-3), obj.name
        assert (c[:, 3] == 1).all()


def test_async_pump_and_cache(native):
    j = _job(native, scenes_np.furnace(2)).prepare().start()
    assert j.pump(timeout=300)
    assert j.state == job.DONE and not j.is_cached
    again = _job(native, scenes_np.furnace(2)).prepare()
    assert again.is_cached and again.run().state == job.DONE
    assert all(np.array_equal(a, b) for a, b in zip(again.radiance(), j.radiance()))
    changed = scenes_np.furnace(2, e=2.0)
    assert not _job(native, changed).prepare().is_cached
    other_preset = _job(native, scenes_np.furnace(2), preset="MEDIUM").prepare()
    assert not other_preset.is_cached


def test_mirrored_object_maps_back(native):
    """Reversing a polygon's winding for the solver and mapping results back gives the Blender
    corner order: the permuted object's result equals the directly-wound one's."""
    from radiosity.core.corners import reverse_polygon_permutation
    si = scenes_np.furnace(2)
    ref = _job(native, si, key=None).prepare().run().radiance()
    si2 = scenes_np.furnace(2)
    o = si2.objects[0]
    # Present side0 with reversed winding (as a mirrored object arrives from Blender) plus the
    # permutation that restores it.
    perm = reverse_polygon_permutation(o.loop_starts, o.loop_totals)
    o.corner_verts = o.corner_verts[perm]
    o.corner_perm = perm
    got = _job(native, si2, key=None).prepare().run().radiance()
    assert np.allclose(got[0][perm], ref[0], rtol=1e-3)


def test_native_rejects_bad_reflectance(native):
    si = scenes_np.furnace(1)
    si.objects[1].reflectance = np.full_like(si.objects[1].reflectance, 1.5)
    with pytest.raises(ValueError, match="side1"):
        _job(native, si).prepare()


def test_cancel_leaves_no_results(native):
    j = _job(native, scenes_np.furnace(2)).prepare().start()
    j.cancel()
    if j.state == job.CANCELLED:
        with pytest.raises(RuntimeError):
            j.radiance()
        assert session.kept("scene") is None


def test_corner_map_gathers_only_the_corners_read(native):
    """A modifier's corner map (the written mesh's corners read a few evaluated corners): the
    solver is told which corners are read and gathers there only; those read what a bake of
    every corner gives them."""
    si = scenes_np.room()
    full = _job(native, si, key=None).prepare().run()
    box = next(i for i, o in enumerate(si.objects) if o.name == "box")
    o = si.objects[box]
    # The written mesh reads corners 0, 2, 4, ... of the box (some twice).
    cmap = np.repeat(np.arange(0, o.corner_count, 2), 2)
    o.corner_map = cmap
    part = _job(native, si, key=None).prepare().run()
    got = part.radiance()[box][cmap]
    assert np.all(np.isfinite(got))
    want = full.radiance()[box][cmap]
    assert abs(got.mean() / want.mean() - 1) < 0.05
    before, after = full.native_stats(), part.native_stats()
    if "gather_corners" in before:  # (the stand-in does not count them)
        read = len(np.unique(cmap))
        assert after["gather_corners"] == before["gather_corners"] - o.corner_count + read
