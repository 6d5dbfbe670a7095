"""Gridded quads and boxes as plain vertex and face lists (numpy only, no bpy).

Blender scripts reach them through rt_common; the core tests' numpy scenes (tests/addon_core)
import this module too, so the two suites build the same geometry from one definition."""
import numpy as np


def grid(origin, u, v, n):
    """n x n quads spanning origin + [0,1]u + [0,1]v; normal = u x v."""
    origin, u, v = (np.asarray(x, dtype=float) for x in (origin, u, v))
    verts = [origin + (i / n) * u + (j / n) * v for j in range(n + 1) for i in range(n + 1)]
    faces = [(j * (n + 1) + i, j * (n + 1) + i + 1, (j + 1) * (n + 1) + i + 1,
              (j + 1) * (n + 1) + i) for j in range(n) for i in range(n)]
    return verts, faces


def gridded_box(center, half, n):
    """Axis-aligned box, faces outward, each side n x n quads (grid()); sides in the order
    -x, +x, -y, +y, -z, +z. Returns (verts, faces) of one mesh."""
    c, h = np.asarray(center, float), np.asarray(half, float)
    bv, bf = [], []
    for axis in range(3):
        for sign in (-1, 1):
            o = c.copy()
            o[axis] += sign * h[axis]
            a1, a2 = [k for k in range(3) if k != axis]
            u = np.zeros(3); u[a1] = 2 * h[a1]
            v = np.zeros(3); v[a2] = 2 * h[a2]
            if np.cross(u, v)[axis] * sign < 0:
                u, v = v, u                     # keep u x v pointing outward
            o = o - u / 2 - v / 2
            gv, gf = grid(o, u, v, n)
            base = len(bv)
            bv += list(gv)
            bf += [tuple(i + base for i in f) for f in gf]
    return bv, bf
