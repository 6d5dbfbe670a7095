"""Blender lights and world -> solver input, in Cycles' units (bpy-free).

Cycles' conversions (how they were measured: docs/decisions.md, "Reference and materials";
tests/blender/test_light_units.py holds every supported Blender to them):

* point, spot: radiant intensity I = power x colour / (4 pi) W/sr in both versions, irradiance
  I cos / d^2; with a radius, the light is a disk of that radius facing the shaded point
  (the same in 3.4 and 5.0);
* spot cone: smoothstep over the outer (1 - cos(size/2)) x blend of the cosine to the axis;
  Blender 3.x also multiplies by that cosine (spot_cos_falloff), 5.0 does not;
* sun: irradiance = strength x colour on a surface facing it (W/m^2), both versions;
* area: one-sided Lambertian emitter of radiance power x colour / (4 A) in 3.4, and
  power x colour / (pi A) in 5.0 (A the light's area, pi/4 size_x size_y for disk/ellipse);
  4.0 is taken as the boundary;
* world: radiance = Background colour x strength, both versions;
* the light's diffuse factor: ignored by Cycles 3.4 and 5.0; we honour it, as EEVEE
  does (default 1 = Cycles' result), and ray visibility "Diffuse" off means no diffuse light.
"""
from dataclasses import dataclass
import hashlib
import math

import numpy as np

POINT, SPOT, SUN, SKY = "POINT", "SPOT", "SUN", "SKY"
DISK_SEGMENTS = 8


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
    # SKY: the world's radiance per direction, float32 (H, W, 3) equirectangular in Blender's
    # convention (native/include/radiosity/environment.h), a factor to `intensity`; None: uniform.
    env: object = None

    def key(self):
        """Everything the solver sees, for change detection and the fingerprint."""
        env = None
        if self.env is not None:
            a = np.ascontiguousarray(self.env, dtype=np.float32)
            env = (a.shape, hashlib.blake2b(a.tobytes(), digest_size=16).hexdigest())
        return (self.name, self.kind, tuple(np.round(self.intensity, 9)), tuple(np.round(self.position, 9)),
                tuple(np.round(self.direction, 9)), round(self.radius, 9), round(self.angle, 9),
                round(self.spot_size, 9), round(self.spot_blend, 9), bool(self.spot_cos_falloff), env)


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
    sqrt(2 pi / (n sin(2 pi / n))), 5.5 % at 8), so the emitted power matches Cycles."""
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
    area light facing the light's -Z: one quad for squares and rectangles; disks and ellipses
    as an equal-area octagon in three quads. Few large pieces matter: the solver's oracle judges
    each emitter piece's link on its own, so a light cut into thirty slivers refines what it
    lights far less (docs/decisions.md, "Reference and materials"); the octagon's outline
    differs from the disk only in the penumbrae."""
    local = area_polygon_local(shape, size_x, size_y, segments)
    n = len(local)
    verts = local
    if n == 4:
        polys = [[0, 1, 2, 3]]
    else:
        # The octagon as two trapezoids around a rectangle (3 quads, the largest pieces).
        polys = [[0, 1, 2, 3], [0, 3, 4, 7], [4, 5, 6, 7]]
    world = transform(verts, matrix)
    m = np.asarray(matrix, float)
    if np.linalg.det(m[:3, :3]) < 0:
        polys = [p[::-1] for p in polys]    # a mirroring matrix reverses the winding
    totals = np.array([len(p) for p in polys], np.int32)
    starts = np.concatenate([[0], np.cumsum(totals)[:-1]]).astype(np.int32)
    corner_verts = np.array([i for p in polys for i in p], np.int32)
    # World area (object scale included, as Cycles' axisu/axisv lengths).
    sx = np.linalg.norm(m[:3, 0]) * size_x
    sy = np.linalg.norm(m[:3, 1]) * size_y
    return world, starts, totals, corner_verts, area_of(shape, sx, sy)


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
    if li.env is not None:
        L.set_environment(np.ascontiguousarray(li.env, dtype=np.float64))
    return L
