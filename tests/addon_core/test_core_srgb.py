"""The sRGB byte copy's maths (core/srgb.py), without Blender."""
import numpy as np
import pytest

from radiosity.core import job, presets, srgb

import scenes_np


def test_known_values():
    rad = np.array([[0.0, 1.0, 0.5], [0.0031308, 0.18, 2.0], [-1.0, 1e30, 0.04045 / 12.92]])
    b = srgb.radiance_to_srgb_bytes(rad)
    assert b.dtype == np.uint8 and b.shape == (3, 4)
    # 0.5 -> 0.7354 -> 187.5 + rounding; 0.18 -> 0.4614 -> 117.7; 0.0031308 -> 0.04045 -> 10.3
    assert b[0].tolist() == [0, 255, 188, 255]
    assert b[1].tolist() == [10, 118, 255, 255]
    assert b[2].tolist() == [0, 255, 10, 255]      # negative -> 0, huge -> 255 (clamped)


def test_exposure_is_stops():
    rad = np.full((1, 3), 0.125)
    assert srgb.radiance_to_srgb_bytes(rad, 2.0)[0, 0] == 188      # 0.125 * 4 = 0.5
    assert srgb.radiance_to_srgb_bytes(rad, 3.0)[0, 0] == 255      # 1.0
    assert srgb.radiance_to_srgb_bytes(rad, -60.0)[0, 0] == 0


def test_encoding_is_monotonic_and_inverts():
    x = np.linspace(0, 1, 4097)
    b = srgb.radiance_to_srgb_bytes(np.stack([x] * 3, axis=1))[:, 0].astype(int)
    assert np.all(np.diff(b) >= 0) and b[0] == 0 and b[-1] == 255
    # Decoding a byte gives back a linear value whose encoding is within half a byte.
    s = b / 255.0
    lin = np.where(s <= 0.04045, s / 12.92, ((s + 0.055) / 1.055) ** 2.4)
    assert np.all(np.abs(srgb.srgb_encode(lin) * 255 - b) < 1e-6 + 0.5)
    assert np.all(np.abs(srgb.srgb_encode(x) * 255 - b) <= 0.5 + 1e-9)


def test_bad_input():
    with pytest.raises(ValueError):
        srgb.radiance_to_srgb_bytes(np.zeros((2, 4)))
    with pytest.raises(ValueError):
        srgb.radiance_to_srgb_bytes(np.array([[np.nan, 0, 0]]))
    with pytest.raises(ValueError):
        srgb.radiance_to_srgb_bytes(np.zeros((1, 3)), float("inf"))
    with pytest.raises(ValueError):
        srgb.radiance_to_srgb_bytes(np.zeros((1, 3)), 1e6)


def test_color_srgb_floats_round_back_to_the_bytes():
    b = np.arange(256, dtype=np.uint8).repeat(4).reshape(-1, 4)
    f = srgb.bytes_to_color_srgb(b)
    assert f.dtype == np.float32 and f.shape == (256 * 4,)
    # Blender stores a float f as the byte floor(f * 255 + 0.5).
    assert np.array_equal(np.floor(f * 255 + 0.5).astype(int), b.ravel())


def test_furnace_bytes_through_the_job(native):
    """B = E / (1 - rho) = 2 everywhere: exposure -1 gives 255, -2 gives 188 on every corner."""
    j = job.SolveJob(native, scenes_np.furnace(n=2), presets.make_settings(native, "DRAFT"),
                     presets.settings_key("DRAFT", 0.05)).prepare().run()
    for exposure, byte in ((-1.0, 255), (-2.0, 188)):
        items = j.srgb_bytes(exposure)
        assert len(items) == 6
        for obj, b in items:
            assert b.shape == (obj.corner_count, 4)
            assert np.abs(b[:, :3].astype(int) - byte).max() <= 1, (exposure, obj.name)
            assert np.all(b[:, 3] == 255)
    assert srgb.byte_attribute_name("Radiosity") == "Radiosity_sRGB"
