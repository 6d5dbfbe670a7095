import json

import numpy as np
import pytest

from radiosity.core import corners, presets, scene_data, stats
from radiosity.core.live import LiveState, TransformCache

import scenes_np


# -- presets ----------------------------------------------------------------------------------
def test_named_presets_map_to_native(native):
    for name in presets.NATIVE_PRESETS:
        s = presets.make_settings(native, name, 0.123)
        assert s.error_threshold == pytest.approx(native.Settings.preset(name).error_threshold)


def test_custom_is_medium_with_threshold(native):
    s = presets.make_settings(native, "CUSTOM", 0.0123)
    base = native.Settings.preset("MEDIUM")
    assert s.error_threshold == pytest.approx(0.0123)
    assert s.rays_per_link == base.rays_per_link


def test_bad_presets(native):
    with pytest.raises(ValueError):
        presets.make_settings(native, "ULTRA")
    with pytest.raises(ValueError):
        presets.make_settings(native, "CUSTOM", 0.0)


def test_settings_key_ignores_threshold_of_named_presets():
    assert presets.settings_key("HIGH", 0.1) == presets.settings_key("HIGH", 0.2)
    assert presets.settings_key("CUSTOM", 0.1) != presets.settings_key("CUSTOM", 0.2)


# -- stats ------------------------------------------------------------------------------------
def test_stats_have_required_keys_and_defaults():
    st = stats.make_stats("full", 1.5, {"elements": 10, "links": 7.0, "capped": False,
                                        "warnings": ["x"]},
                          {"objects": 3, "elements": 99}, {"cached": True, "mode": "bad"})
    assert set(stats.REQUIRED_KEYS) <= set(st)
    assert st["mode"] == "full" and st["elements"] == 10 and st["links"] == 7
    assert st["objects"] == 3 and st["rays"] == 0 and st["cached"] is True
    assert "warnings" not in st            # non-scalars are not copied
    assert stats.from_json(stats.to_json(st)) == json.loads(json.dumps(st))
    with pytest.raises(ValueError):
        stats.make_stats("partial", 0, {})


# -- corners ----------------------------------------------------------------------------------
def test_rgba_assembly():
    rad = np.arange(12, dtype=np.float32).reshape(4, 3)
    rgba = corners.radiance_to_rgba(rad, 4)
    assert rgba.dtype == np.float32 and rgba.shape == (16,)
    assert np.array_equal(rgba.reshape(4, 4)[:, :3], rad)
    assert (rgba.reshape(4, 4)[:, 3] == 1).all()
    with pytest.raises(ValueError):
        corners.radiance_to_rgba(rad, 5)
    rad[1, 1] = np.nan
    with pytest.raises(ValueError):
        corners.radiance_to_rgba(rad)


def test_reverse_polygon_permutation():
    starts, totals = np.array([0, 3, 7]), np.array([3, 4, 3])
    perm = corners.reverse_polygon_permutation(starts, totals)
    assert perm.tolist() == [2, 1, 0, 6, 5, 4, 3, 9, 8, 7]
    assert np.array_equal(perm[perm], np.arange(10))     # an involution


# -- scene data -------------------------------------------------------------------------------
def test_validation_names_object_and_problem():
    si = scenes_np.furnace(1)
    si.objects[2].vertices = si.objects[2].vertices.copy()
    si.objects[2].vertices[1, 0] = np.nan
    with pytest.raises(scene_data.InputError, match="side2.*vertex 1.*NaN"):
        scene_data.validate(si)
    si = scenes_np.furnace(1)
    si.objects[0].corner_verts = si.objects[0].corner_verts.copy()
    si.objects[0].corner_verts[0] = 99
    with pytest.raises(scene_data.InputError, match="side0.*vertex that does not exist"):
        scene_data.validate(si)
    with pytest.raises(scene_data.InputError, match="nothing to bake"):
        scene_data.validate(scene_data.SceneInput())


def test_face_table_and_clamps():
    t = scene_data.face_table([[0.1, 0.2, 0.3], [1, 1, 1]], np.array([0, 1, 5, -1]), [0.8] * 3)
    assert t.shape == (4, 3) and t[2].tolist() == [1, 1, 1] and np.allclose(t[3], [.1, .2, .3])
    assert np.allclose(scene_data.face_table([], np.array([0, 0]), [0.8] * 3), 0.8)
    assert scene_data.clamp_reflectance([1.5, -1, 0.5]).tolist() == pytest.approx(
        [scene_data.MAX_REFLECTANCE, 0, 0.5])
    assert scene_data.clamp_emission([-1, 2, 0]).tolist() == [0, 2, 0]


def test_fingerprint_tracks_geometry_materials_settings():
    a, b = scenes_np.furnace(1), scenes_np.furnace(1)
    key = presets.settings_key("MEDIUM", 0.05)
    assert scene_data.fingerprint(a, key) == scene_data.fingerprint(b, key)
    assert scene_data.fingerprint(a, key) != scene_data.fingerprint(
        a, presets.settings_key("HIGH", 0.05))
    b.objects[0].vertices = b.objects[0].vertices + 1e-9
    assert scene_data.fingerprint(a, key) != scene_data.fingerprint(b, key)
    c = scenes_np.furnace(1)
    c.objects[3].emission = c.objects[3].emission * 2
    assert scene_data.fingerprint(a, key) != scene_data.fingerprint(c, key)


# -- live state -------------------------------------------------------------------------------
def test_transform_cache_and_debounce():
    tc = TransformCache()
    m = np.eye(4)
    assert not tc.moved("a", m)            # never baked -> ignored
    tc.remember("a", m)
    assert not tc.moved("a", m.copy())
    m2 = m.copy(); m2[0, 3] = 0.5
    assert tc.moved("a", m2)
    st = LiveState()
    st.request(now=10.0)
    assert st.pending and not st.due(now=10.1) and st.due(now=10.5)
    assert st.take() and not st.pending and not st.take()


def test_a_slow_viewport_s_frames_postpone_the_pause():
    """A frame drawn after a move postpones the update (the viewport could not take the drag's
    next move meanwhile); only the first PAUSE_FRAMES frames do; without a move nothing is
    pending and frames change nothing."""
    from radiosity.core.live import DEBOUNCE_SECONDS as D, PAUSE_FRAMES
    st = LiveState()
    st.drawn(now=1.0)
    assert not st.pending
    st.request(now=10.0)
    st.drawn(now=11.0)                      # a one-second frame after the move
    assert not st.due(now=10.0 + D + 0.01) and st.due(now=11.0 + D)
    st.request(now=11.2)                    # the drag's next step: the count starts again
    t = 11.2
    for _ in range(PAUSE_FRAMES + 3):       # a viewport that never stops drawing
        t += 0.5
        st.drawn(now=t)
    last = 11.2 + 0.5 * PAUSE_FRAMES
    assert not st.due(now=last + D - 0.01) and st.due(now=last + D)
