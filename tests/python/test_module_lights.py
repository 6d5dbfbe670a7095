"""The binding of lights, lighting-only output and leaf meshes (radiosity_native)."""
import math

import numpy as np
import pytest

import radtest_scenes as S


def _floor(rn, rho=0.5, n=6):
    floor = S.grid(np.array([[-2, -2, 0], [2, -2, 0], [2, 2, 0], [-2, 2, 0]], float), n, n)
    sc = rn.Scene()
    floor.add(sc, "floor", rho=rho)
    return sc, floor


def _point(rn, pos=(0.3, -0.2, 1.5), intensity=2.0, radius=0.0):
    L = rn.Light()
    L.name = "lamp"
    L.type = rn.LightType.POINT
    L.position = pos
    L.radius = radius
    L.intensity = (intensity,) * 3
    return L


def test_light_fields_round_trip(rn):
    L = rn.Light()
    L.type = rn.LightType.SPOT
    L.position = (1, 2, 3)
    L.direction = (0, 0, -2)
    L.spot_size, L.spot_blend, L.spot_cos_falloff = 1.0, 0.25, True
    L.intensity = (1, 2, 3)
    assert L.position == pytest.approx((1, 2, 3)) and L.intensity == pytest.approx((1, 2, 3))
    sc, _ = _floor(rn)
    assert sc.add_light(L) == 0 and sc.light_count == 1


@pytest.mark.parametrize("field,value", [("intensity", (-1.0, 0.0, 0.0)), ("radius", -1.0),
                                         ("spot_blend", 2.0), ("position", (float("nan"), 0.0, 0.0))])
def test_bad_lights_are_refused_by_name(rn, field, value):
    sc, _ = _floor(rn)
    L = _point(rn)
    L.name = "Bad Lamp"
    setattr(L, field, value)
    with pytest.raises(ValueError, match="Bad Lamp"):
        sc.add_light(L)


def test_point_light_alone_lights_the_scene(rn):
    sc, floor = _floor(rn)
    sc.add_light(_point(rn, intensity=2.0))
    s = rn.Solver(sc, rn.Settings.preset("MEDIUM"))
    s.solve()
    out = s.corner_radiance(0)[:, 0]
    p = floor.corner_positions()
    v = np.array([0.3, -0.2, 1.5]) - p
    d2 = (v ** 2).sum(1)
    ref = 0.5 * 2.0 * v[:, 2] / np.sqrt(d2) / d2 / math.pi
    # MEDIUM, coarse 6x6 floor: corners at the rim read the mean of the leaf beside them
    # (the HIGH figure, 2 %, is in tests/native/test_lights.cpp).
    assert np.sqrt(np.mean((out - ref) ** 2)) / np.sqrt(np.mean(ref ** 2)) < 0.08
    assert s.stats()["no_emitters"] is False and s.stats()["elements"] > 0


def test_set_light_goes_through_update(rn):
    sc, _ = _floor(rn)
    sc.add_light(_point(rn, intensity=2.0))
    s = rn.Solver(sc, rn.Settings.preset("MEDIUM"))
    s.solve()
    before = s.corner_radiance(0)
    s.set_light(0, _point(rn, intensity=1.0))
    s.update()
    assert s.stats()["mode"] == "incremental"
    assert np.allclose(s.corner_radiance(0), 0.5 * before, rtol=1e-3, atol=1e-7)
    with pytest.raises(ValueError):
        s.set_light(3, _point(rn))


def test_lighting_only_and_leaf_mesh(rn):
    sc, floor = _floor(rn, rho=0.25)
    sc.add_light(_point(rn, intensity=2.0, radius=0.1))
    s = rn.Solver(sc, rn.Settings.preset("MEDIUM"))
    s.solve()
    assert np.allclose(s.corner_irradiance(0) * 0.25, s.corner_radiance(0), rtol=1e-4, atol=1e-7)
    m = s.leaf_mesh(0)
    assert m["vertices"].shape[1] == 3 and m["values"].shape == (len(m["loop_totals"]), 3)
    assert int(m["loop_totals"].sum()) == len(m["corner_verts"])
    assert len(m["loop_totals"]) >= floor.polygons
    lo = s.leaf_mesh(0, lighting_only=True)
    assert np.allclose(lo["values"] * 0.25, m["values"], rtol=1e-4, atol=1e-7)


def test_non_occluding_one_sided_object(rn):
    sc, _ = _floor(rn)
    v = np.array([[-1, -1, 1], [-1, 1, 1], [1, 1, 1], [1, -1, 1]], float)   # faces -z
    sc.add_object("area", -1, v, np.array([0], np.int32), np.array([4], np.int32),
                  np.arange(4, dtype=np.int32), np.zeros((1, 3), np.float32),
                  np.full((1, 3), 3.0, np.float32), np.zeros(1, np.uint8), occluder=False)
    sc.add_light(_point(rn, pos=(0, 0, 2), intensity=2.0))
    s = rn.Solver(sc, rn.Settings.preset("MEDIUM"))
    s.solve()
    # The point light above shines through the area light onto the floor below it.
    direct = 0.5 * 2.0 / 4.0 / math.pi
    assert s.radiance_at(0, 14, (0.1, 0.1, 0.0))[0] > direct
