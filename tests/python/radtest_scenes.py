"""Small scenes built with numpy for the radiosity_native tests, in Blender's polygon layout
(vertices, loop_starts, loop_totals, corner_verts), mirroring native/src/builtin_scenes.cpp,
plus the analytic view factors of NOTES.md."""
import math
from dataclasses import dataclass

import numpy as np


@dataclass
class Mesh:
    vertices: np.ndarray      # float64 (V,3)
    loop_starts: np.ndarray   # int32 (F,)
    loop_totals: np.ndarray   # int32 (F,)
    corner_verts: np.ndarray  # int32 (C,)

    @property
    def polygons(self):
        return len(self.loop_starts)

    @property
    def corners(self):
        return len(self.corner_verts)

    def scaled(self, k):
        return Mesh(self.vertices * k, self.loop_starts, self.loop_totals, self.corner_verts)

    def corner_positions(self):
        return self.vertices[self.corner_verts]

    def face_of_corner(self):
        return np.repeat(np.arange(self.polygons), self.loop_totals)

    def add(self, scene, name, cluster=-1, rho=0.5, emission=0.0, two_sided=None):
        """Adds the mesh as one object; rho / emission: scalar, RGB or (F,3)."""
        F = self.polygons
        rho = np.broadcast_to(np.asarray(rho, np.float32), (F, 3)).copy() if np.ndim(rho) < 2 else rho
        emission = (np.broadcast_to(np.asarray(emission, np.float32), (F, 3)).copy()
                    if np.ndim(emission) < 2 else emission)
        if two_sided is not None and np.ndim(two_sided) == 0:
            two_sided = np.full(F, bool(two_sided))
        return scene.add_object(name, cluster, self.vertices, self.loop_starts, self.loop_totals,
                                self.corner_verts, rho, emission, two_sided)


def grid(q, nu, nv):
    """Planar quad q[0..3] (counter-clockwise about its front normal) as an nu x nv grid,
    vertex layout and winding as scenes::add_grid."""
    q = np.asarray(q, np.float64)
    u = np.arange(nu + 1) / nu
    v = np.arange(nv + 1) / nv
    U, V = np.meshgrid(u, v)  # rows: v, columns: u
    U = U.reshape(-1, 1)
    V = V.reshape(-1, 1)
    verts = q[0] * ((1 - U) * (1 - V)) + q[1] * (U * (1 - V)) + q[2] * (U * V) + q[3] * ((1 - U) * V)
    j, i = np.meshgrid(np.arange(nv), np.arange(nu), indexing="ij")
    a = (j * (nu + 1) + i).reshape(-1)
    cv = np.stack([a, a + 1, a + nu + 2, a + nu + 1], axis=1).reshape(-1)
    F = nu * nv
    return Mesh(verts, (np.arange(F) * 4).astype(np.int32), np.full(F, 4, np.int32), cv.astype(np.int32))


def merge(meshes):
    V, LS, LT, CV = [], [], [], []
    vbase = cbase = 0
    for m in meshes:
        V.append(m.vertices)
        LS.append(m.loop_starts + cbase)
        LT.append(m.loop_totals)
        CV.append(m.corner_verts + vbase)
        vbase += len(m.vertices)
        cbase += m.corners
    return Mesh(np.concatenate(V), np.concatenate(LS).astype(np.int32), np.concatenate(LT).astype(np.int32),
                np.concatenate(CV).astype(np.int32))


def box(lo, hi, n, inward=False):
    """Axis-aligned box, n x n quads per face, vertices duplicated per face (as scenes::add_box).
    Face order -z, +z, -y, +y, -x, +x; face k owns polygons [k*n*n, (k+1)*n*n)."""
    lo = np.asarray(lo, float)
    hi = np.asarray(hi, float)

    def P(x, y, z):
        return [hi[0] if x else lo[0], hi[1] if y else lo[1], hi[2] if z else lo[2]]

    faces = [
        [P(0, 0, 0), P(0, 1, 0), P(1, 1, 0), P(1, 0, 0)],
        [P(0, 0, 1), P(1, 0, 1), P(1, 1, 1), P(0, 1, 1)],
        [P(0, 0, 0), P(1, 0, 0), P(1, 0, 1), P(0, 0, 1)],
        [P(0, 1, 0), P(0, 1, 1), P(1, 1, 1), P(1, 1, 0)],
        [P(0, 0, 0), P(0, 0, 1), P(0, 1, 1), P(0, 1, 0)],
        [P(1, 0, 0), P(1, 1, 0), P(1, 1, 1), P(1, 0, 1)],
    ]
    meshes = []
    for q in faces:
        if inward:
            q[1], q[3] = q[3], q[1]
        meshes.append(grid(q, n, n))
    return merge(meshes)


def polygon(verts):
    """One n-gon."""
    verts = np.asarray(verts, np.float64)
    n = len(verts)
    return Mesh(verts, np.array([0], np.int32), np.array([n], np.int32), np.arange(n, dtype=np.int32))


def square(cx, cy, z, size, n=1, facing_up=True):
    h = size / 2
    if facing_up:
        q = [[cx - h, cy - h, z], [cx + h, cy - h, z], [cx + h, cy + h, z], [cx - h, cy + h, z]]
    else:
        q = [[cx - h, cy - h, z], [cx - h, cy + h, z], [cx + h, cy + h, z], [cx + h, cy - h, z]]
    return grid(q, n, n)


def face_normals(mesh):
    out = []
    for s, t in zip(mesh.loop_starts, mesh.loop_totals):
        p = mesh.vertices[mesh.corner_verts[s:s + t]]
        n = np.zeros(3)
        for k in range(t):  # Newell
            a, b = p[k], p[(k + 1) % t]
            n += [(a[1] - b[1]) * (a[2] + b[2]), (a[2] - b[2]) * (a[0] + b[0]), (a[0] - b[0]) * (a[1] + b[1])]
        out.append(n)
    return np.array(out)


# --- analytic view factors (NOTES.md, "Ground truth for tests") ---------------------------

def _f(x, y):
    sx = math.sqrt(1 + x * x)
    sy = math.sqrt(1 + y * y)
    return (x / sx * math.atan(y / sx) + y / sy * math.atan(x / sy)) / (2 * math.pi)


def point_to_rect_on_axis(a, b, h):
    """View factor from a point (normal up) at height h below the centre of an a x b rectangle."""
    return 4 * _f(a / (2 * h), b / (2 * h))


def point_to_rect(px, py, x0, x1, y0, y1, h):
    """View factor from a point (normal +z) at (px,py,0) to the parallel rectangle
    [x0,x1]x[y0,y1] at height h (superposition of corner rectangles)."""
    def corner(X, Y):
        return math.copysign(1, X) * math.copysign(1, Y) * _f(abs(X) / h, abs(Y) / h)
    return corner(x1 - px, y1 - py) - corner(x0 - px, y1 - py) - corner(x1 - px, y0 - py) + corner(x0 - px, y0 - py)
