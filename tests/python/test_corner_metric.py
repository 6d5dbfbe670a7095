"""bench/corner_metric.py, the error every benchmark and Blender test judges against Cycles with
(pure numpy; here beside the module's tests because they run in plain pytest)."""
import os
import sys

import numpy as np
import pytest

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "bench"))
import corner_metric as cm  # noqa: E402


def test_hand_computed():
    # Corners: an emitter, two lit ones, one covered (reference 0 on every channel).
    ref = np.array([[9, 9, 9], [1, 1, 1], [2, 2, 2], [0, 0, 0]], float)
    x = np.array([[0, 0, 0], [1.1, 1.1, 1.1], [2, 2, 2], [0.15, 0.15, 0.15]], float)
    emit = np.array([True, False, False, False])
    e = cm.corner_error(x, ref, emitter=emit)
    assert (e["judged"], e["covered"], e["emitter"]) == (3, 1, 1)
    floor = 0.05 * 1.0                      # mean r over the judged corners, the zero included
    assert e["floor"] == pytest.approx(floor)
    rel2 = np.array([0.1 ** 2, 0.0, (0.15 / floor) ** 2])   # per corner (all channels alike)
    assert e["rrmse"] == pytest.approx(np.sqrt(rel2.mean()))
    assert e["covered_share"] == pytest.approx(rel2[2] / rel2.sum())
    assert e["rrmse_uncovered"] == pytest.approx(np.sqrt(rel2[:2].mean()))
    assert e["rrmse_covered"] == pytest.approx(0.15 / floor)
    abs2 = np.array([0.01, 0.0, 0.0225])
    assert e["nrmse"] == pytest.approx(np.sqrt(abs2.mean() / np.mean([1.0, 4.0, 0.0])))
    assert e["covered_share_abs"] == pytest.approx(abs2[2] / abs2.sum())
    assert e["mean_ratio"] == pytest.approx((1.1 + 2 + 0.15) / 3.0)


def test_exact_and_mask_with_the_scene_floor():
    rng = np.random.default_rng(1)
    ref = rng.uniform(0.1, 1.0, (50, 3))
    ref[:5] = 0.0
    assert cm.corner_error(ref, ref)["rrmse"] == 0.0
    x = ref * 1.1 + 0.01
    floor = cm.scene_floor(ref)
    whole = cm.corner_error(x, ref)
    a = cm.corner_error(x, ref, mask=np.arange(50) < 20, floor=floor)
    b = cm.corner_error(x, ref, mask=np.arange(50) >= 20, floor=floor)
    # With the scene's floor, groups' squared errors add up to the scene's.
    assert 20 * a["rrmse"] ** 2 + 30 * b["rrmse"] ** 2 == pytest.approx(50 * whole["rrmse"] ** 2)


def test_parts_and_noise_removal():
    """k noisy bakes of a known truth: the stored variance predicts the reference's error, and
    removing it in quadrature recovers an independent estimate's true error."""
    rng = np.random.default_rng(7)
    truth = rng.uniform(0.2, 1.0, (20000, 3))
    sigma = 0.3                                           # per-sample noise, spp-weighted parts
    spp = np.array([1024, 4096, 4096, 2048])
    parts = truth + rng.normal(size=(4, *truth.shape)) * sigma / np.sqrt(spp)[:, None, None]
    mean, var = cm.combine_parts(parts, spp)
    assert np.mean(var) == pytest.approx(sigma ** 2 / spp.sum(), rel=0.03)
    e_ref = cm.corner_error(mean, truth)                  # the reference's own true error
    noise = cm.corner_error(mean, mean, ref_var=var)["ref_noise_rrmse"]
    assert noise == pytest.approx(e_ref["rrmse"], rel=0.05)
    ours = truth * (1 + 0.02 * rng.normal(size=truth.shape))   # an estimate 2 % off the truth
    true_err = cm.corner_error(ours, truth)["rrmse"]
    e = cm.corner_error(ours, mean, ref_var=var)
    assert e["rrmse"] > true_err
    assert e["rrmse_denoised"] == pytest.approx(true_err, rel=0.03)
    one, none = cm.combine_parts(parts[:1], spp[:1])
    assert none is None and np.allclose(one, parts[0])


def test_per_object_adds_up_to_the_scene():
    # Two objects' corners one after another; with the scene's floor their squared errors add
    # up to the scene's, and a skipped object is left out.
    rng = np.random.default_rng(3)
    ref = rng.uniform(0.1, 1.0, (10, 3))
    x = ref * rng.uniform(0.9, 1.1, (10, 3))
    floor = cm.scene_floor(ref)
    per = cm.per_object(x, ref, ["A", "B"], [4, 6], floor=floor)
    whole = cm.corner_error(x, ref)
    assert per["A"]["rrmse"] ** 2 * 4 + per["B"]["rrmse"] ** 2 * 6 == pytest.approx(whole["rrmse"] ** 2 * 10)
    assert per["B"]["ours_mean"] == pytest.approx(x[4:].mean(axis=0).tolist())
    assert per["A"]["ref_mean"] == pytest.approx(ref[:4].mean(axis=0).tolist())
    assert list(cm.per_object(x, ref, ["A", "B"], [4, 6], skip=("A",))) == ["B"]
