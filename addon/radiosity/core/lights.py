"""Blender lights and world -> solver input, in Cycles' units (bpy-free).

Cycles' conversions, measured with tests/blender/scripts/measure_light_units.py (a lone
rho = 0.5 floor, COMBINED vertex-colour bake against the analytic irradiance; ratios within
0.1 %; Blender 3.4.1 and PyPI bpy 5.0.1; tests/python/test_light_units.py keeps the figures):

* point, spot: radiant intensity I = power x colour / (4 pi) W/sr in both versions, irradiance
  I cos / d^2; with a radius, the light is a disk of that radius facing the shaded point
  (radius 0.5 at 1.5 m: 0.90-0.98 of the point-light value, the same in 3.4 and 5.0);
* spot cone: smoothstep over the outer (1 - cos(size/2)) x blend of the cosine to the axis;
  Blender 3.x also multiplies by that cosine (spot_cos_falloff), 5.0 does not;
* sun: irradiance = strength x colour on a surface facing it (W/m^2), both versions;
* area: one-sided Lambertian emitter of radiance power x colour / (4 A) in 3.4, and
  power x colour / (pi A) in 5.0 (A the light's area, pi/4 size_x size_y for disk/ellipse);
  4.0 is taken as the boundary (not measured: no 4.x here);
* world: radiance = Background colour x strength, both versions;
* the light's diffuse factor: ignored by Cycles 3.4 and 5.0 (measured); we honour it, as EEVEE
  does (default 1 = Cycles' result), and ray visibility "Diffuse" off means no diffuse light.
"""
from dataclasses import dataclass
import math

import numpy as np

POINT, SPOT, SUN, SKY = "POINT", "SPOT", "SUN", "SKY"
DISK_SEGMENTS = 32


@dataclass
class LightInput:
    """One native LightDesc (native/include/radiosity/lights.h), world space."""
    name: str
    kind: str                       # POINT | SPOT | SUN | SKY
    intensity: tuple                # see lights.h: W/sr (point, spot), W/m^2 (sun), radiance (sky)
    position: tuple = (0.0, 0.0, 0.0)
    direction: tuple = (0.0, 0.0, -1.0)
    radius: float = 0.0
    angle: float = 0.0
    spot_size: float = math.pi
    spot_blend: float = 0.0
    spot_cos_falloff: bool = False

    def key(self):
        """Everything the solver sees, for change detection and the fingerprint."""
        return (self.name, self.kind, tuple(np.round(self.intensity, 9)), tuple(np.round(self.position, 9)),
                tuple(np.round(self.direction, 9)), round(self.radius, 9), round(self.angle, 9),
                round(self.spot_size, 9), round(self.spot_blend, 9), bool(self.spot_cos_falloff))


def area_units_v4(version):
    """Blender 4.0 and later: area radiance P/(pi A); earlier: P/(4 A) (see module doc)."""
    return tuple(version) >= (4, 0, 0)


def point_intensity(power, color, factor=1.0):
    return tuple(float(power) * float(factor) * np.asarray(color, float) / (4.0 * math.pi))


def sun_irradiance(strength, color, factor=1.0):
    return tuple(float(strength) * float(factor) * np.asarray(color, float))


def area_of(shape, size_x, size_y):
    if shape in ("DISK", "ELLIPSE"):
        return math.pi / 4.0 * size_x * size_y
    return size_x * size_y


def area_radiance(power, color, area, version, factor=1.0):
    if not area > 0:
        return (0.0, 0.0, 0.0)
    k = 1.0 / (math.pi * area) if area_units_v4(version) else 1.0 / (4.0 * area)
    return tuple(float(power) * float(factor) * k * np.asarray(color, float))


def area_polygon_local(shape, size_x, size_y, segments=DISK_SEGMENTS):
    """Outline of an area light in its local XY plane, counter-clockwise seen from -Z (the side
    it lights), so the polygon's front normal is local -Z.

    Disks and ellipses become a `segments`-gon whose area equals the ellipse's (radii scaled by
    sqrt(2 pi / (n sin(2 pi / n))), 0.6 % at 32), so the emitted power matches Cycles."""
    hx, hy = 0.5 * size_x, 0.5 * size_y
    if shape in ("DISK", "ELLIPSE"):
        n = int(segments)
        s = math.sqrt(2.0 * math.pi / (n * math.sin(2.0 * math.pi / n)))
        t = -np.arange(n) * 2.0 * math.pi / n          # clockwise from +Z = ccw from -Z
        return np.stack([hx * s * np.cos(t), hy * s * np.sin(t), np.zeros(n)], axis=1)
    return np.array([[-hx, -hy, 0.0], [-hx, hy, 0.0], [hx, hy, 0.0], [hx, -hy, 0.0]])


def transform(points, matrix):
    m = np.asarray(matrix, float)
    return np.asarray(points, float) @ m[:3, :3].T + m[:3, 3]


def area_light_mesh(shape, size_x, size_y, matrix, segments=DISK_SEGMENTS):
    """(world vertices (V,3), loop_starts, loop_totals, corner_verts, world area) of one
    area light as a single polygon facing the light's -Z."""
    local = area_polygon_local(shape, size_x, size_y, segments)
    world = transform(local, matrix)
    n = len(world)
    corner_verts = np.arange(n, dtype=np.int32)
    # A mirroring matrix reverses the winding: keep the front toward the transformed -Z.
    m = np.asarray(matrix, float)
    if np.linalg.det(m[:3, :3]) < 0:
        corner_verts = corner_verts[::-1].copy()
    # World area (object scale included, as Cycles' axisu/axisv lengths).
    sx = np.linalg.norm(m[:3, 0]) * size_x
    sy = np.linalg.norm(m[:3, 1]) * size_y
    return (world, np.array([0], np.int32), np.array([n], np.int32), corner_verts,
            area_of(shape, sx, sy))


def direction_of(matrix):
    """A light's -Z axis in world space (spot axis, sun travel direction)."""
    m = np.asarray(matrix, float)
    d = -m[:3, 2]
    nrm = np.linalg.norm(d)
    return tuple(d / nrm) if nrm > 0 else (0.0, 0.0, -1.0)


def spot_cos_falloff(version):
    return tuple(version) < (4, 0, 0)


def to_native(native, li):
    """LightInput -> native.Light."""
    L = native.Light()
    L.name = li.name
    L.type = getattr(native.LightType, li.kind)
    L.position = tuple(map(float, li.position))
    L.direction = tuple(map(float, li.direction))
    L.radius = float(li.radius)
    L.angle = float(li.angle)
    L.spot_size = float(li.spot_size)
    L.spot_blend = float(li.spot_blend)
    L.spot_cos_falloff = bool(li.spot_cos_falloff)
    L.intensity = tuple(map(float, li.intensity))
    return L
