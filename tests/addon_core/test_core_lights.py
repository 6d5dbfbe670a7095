"""The add-on's light conversions (addon/radiosity/core/lights.py), bpy-free. The measured
Cycles figures they encode are checked in real Blender by tests/blender/test_light_units.py."""
import math

import numpy as np
import pytest

from radiosity.core import lights as L
from radiosity.core import scene_data


def test_unit_conversions_per_blender_generation():
    assert L.point_intensity(4 * math.pi, (1, 0.5, 0))[:2] == pytest.approx((1.0, 0.5))
    assert L.sun_irradiance(3.0, (1, 1, 1), factor=0.5)[0] == pytest.approx(1.5)
    # Area: P / (4 A) before Blender 4.0, P / (pi A) from 4.0 (measured in 3.4.1 and 5.0.1).
    assert L.area_radiance(100, (1, 1, 1), 2.0, (3, 4, 1))[0] == pytest.approx(12.5)
    assert L.area_radiance(100, (1, 1, 1), 2.0, (5, 0, 1))[0] == pytest.approx(100 / (2 * math.pi))
    assert L.area_of("DISK", 2, 2) == pytest.approx(math.pi)
    assert L.area_of("ELLIPSE", 2, 1) == pytest.approx(math.pi / 2)
    assert L.spot_cos_falloff((3, 6, 0)) and not L.spot_cos_falloff((4, 2, 0))


def _polys(verts, starts, totals, cverts):
    return [verts[cverts[s:s + t]] for s, t in zip(starts, totals)]


def _normal_area(p):
    n = sum(np.cross(p[k] - p[0], p[k + 1] - p[0]) for k in range(1, len(p) - 1)) / 2
    return n / np.linalg.norm(n), np.linalg.norm(n)


@pytest.mark.parametrize("shape,sx,sy", [("SQUARE", 1, 1), ("RECTANGLE", 2, 0.5), ("DISK", 1, 1),
                                         ("ELLIPSE", 1.5, 0.5)])
def test_area_light_mesh_faces_minus_z_with_the_lights_area(shape, sx, sy):
    # Rotated 90 deg about X: local -Z becomes world +Y; scaled x2 in local x.
    c, s = 0.0, 1.0
    m = np.array([[2, 0, 0, 1], [0, c, -s, 2], [0, s, c, 3], [0, 0, 0, 1]], float)
    verts, starts, totals, cverts, area = L.area_light_mesh(shape, sx, sy, m)
    total = 0.0
    for p in _polys(verts, starts, totals, cverts):
        n, a = _normal_area(p)
        assert n == pytest.approx([0, 1, 0], abs=1e-9)
        total += a
    assert area == pytest.approx(L.area_of(shape, 2 * sx, sy))
    assert total == pytest.approx(area, rel=1e-9)     # the octagon keeps the ellipse's area
    assert len(starts) <= 3                            # few, large pieces (see area_light_mesh)


def test_mirrored_area_light_still_faces_its_minus_z():
    m = np.diag([-1.0, 1.0, 1.0, 1.0])
    verts, starts, totals, cverts, _ = L.area_light_mesh("SQUARE", 1, 1, m)
    n, _ = _normal_area(_polys(verts, starts, totals, cverts)[0])
    assert n == pytest.approx([0, 0, -1])


def test_lights_enter_fingerprint_and_emitter_check():
    si = scene_data.SceneInput()
    assert not si.has_emitter()
    si.lights.append(L.LightInput("lamp", L.POINT, (1.0, 1.0, 1.0), position=(0, 0, 1)))
    assert si.has_emitter()
    a = scene_data.fingerprint(si, ("MEDIUM",))
    si.lights[0] = L.LightInput("lamp", L.POINT, (1.0, 1.0, 1.0), position=(0, 0, 2))
    assert scene_data.fingerprint(si, ("MEDIUM",)) != a
