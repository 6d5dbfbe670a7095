"""Cycles' light unit conversions, measured in the Blender under test (both flavours) and checked
against the conversions the add-on uses (addon/radiosity/core/lights.py): a lone rho = 0.5 floor
lit by one light, a COMBINED vertex bake (no interreflection: exactly rho E / pi) against the
analytic irradiance of our conversion. tests/blender/scripts/measure_light_units.py makes the
bake."""
import importlib.util
import json
import math
import os

import numpy as np
import pytest

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.dirname(os.path.dirname(HERE))
RHO = 0.5


def _core_lights():
    spec = importlib.util.spec_from_file_location(
        "core_lights", os.path.join(REPO, "addon", "radiosity", "core", "lights.py"))
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


def _point_E(pos, lp, intensity):
    v = np.asarray(lp) - pos
    d2 = (v ** 2).sum(1)
    return intensity * (v[:, 2] / np.sqrt(d2)) / d2


def _rect_f(pos, c, a, b, disk=False, n=240):
    """Irradiance per unit radiance under a downward-facing a x b rectangle (or disk)."""
    xs = (np.arange(n) + 0.5) / n - 0.5
    X, Y = np.meshgrid(xs * a, xs * b)
    m = (X / (a / 2)) ** 2 + (Y / (b / 2)) ** 2 <= 1 if disk else np.ones_like(X, bool)
    X, Y = X[m] + c[0], Y[m] + c[1]
    dA = a * b / n / n
    out = []
    for p in pos:
        dz = c[2] - p[2]
        r2 = (X - p[0]) ** 2 + (Y - p[1]) ** 2 + dz * dz
        out.append((dz * dz / r2 / r2).sum() * dA)
    return np.array(out)


def test_cycles_units_match_our_conversions(run_blender):
    out = os.path.join(str(run_blender.tmp_path), "units.json")
    r = run_blender("measure_light_units.py", "--samples", "256", "--out", out,
                    "--cases", "point,point_diffuse,spot,sun,area_square,area_disk,world")
    assert r["ok"], r["_log"]
    data = json.load(open(out))
    version = tuple(int(x) for x in data["blender"].split(" ")[0].split(".")[:2])
    cl = _core_lights()
    ratios = {}
    for case, v in data["cases"].items():
        pos, rgb = np.array(v["pos"]), np.array(v["rgb"])[:, 0]
        if case.startswith("point"):
            pred = RHO * _point_E(pos, (0.3, -0.2, 1.5), cl.point_intensity(100.0, (1, 1, 1))[0]) / math.pi
        elif case == "spot":
            E = _point_E(pos, (0, 0, 1), cl.point_intensity(100.0, (1, 1, 1))[0])
            cos_axis = (1 - pos[:, 2]) / np.linalg.norm(pos - np.array([0, 0, 1.0]), axis=1)
            mask = (cos_axis > math.cos(math.radians(45))) * (cos_axis if cl.spot_cos_falloff(version) else 1.0)
            pred = RHO * E * mask / math.pi
        elif case == "sun":
            pred = np.full(len(pos), RHO * cl.sun_irradiance(2.0, (1, 1, 1))[0] * math.cos(math.radians(30)) / math.pi)
        elif case == "area_square":
            L = cl.area_radiance(100.0, (1, 1, 1), cl.area_of("SQUARE", 1, 1), version)[0]
            pred = RHO * L * _rect_f(pos, (0, 0, 1), 1, 1) / math.pi
        elif case == "area_disk":
            L = cl.area_radiance(100.0, (1, 1, 1), cl.area_of("DISK", 1, 1), version)[0]
            pred = RHO * L * _rect_f(pos, (0, 0, 1), 1, 1, disk=True) / math.pi
        elif case == "world":
            pred = np.full(len(pos), RHO * 0.4 * 1.5)
        else:
            continue
        ok = pred > 0.05 * pred.max()
        # Away from the spot's edge (where the light's radius blurs the cone).
        if case == "spot":
            ok &= np.abs(cos_axis - math.cos(math.radians(45))) > 0.03
        ratios[case] = float(np.median(rgb[ok] / pred[ok]))
    print(f"\n[{r['_flavour']} {data['blender']}] Cycles / ours: " +
          ", ".join(f"{k} {v:.4f}" for k, v in ratios.items()))
    for case, ratio in ratios.items():
        if case == "point_diffuse":
            continue    # Cycles ignores the diffuse factor (we honour it; default 1 agrees)
        assert abs(ratio - 1) < 0.02, (case, ratio, data["blender"])
