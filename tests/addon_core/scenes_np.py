"""numpy-only test scenes for the core tests."""
import os
import sys

import numpy as np

from radiosity.core.scene_data import ObjectInput, SceneInput

# The Blender tests' bpy-free geometry: open_floor builds the box they build.
sys.path.append(os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "blender", "scripts"))
from box_grid import gridded_box  # noqa: E402


def grid(origin, u, v, n):
    origin, u, v = (np.asarray(x, float) for x in (origin, u, v))
    verts = np.array([origin + (i / n) * u + (j / n) * v
                      for j in range(n + 1) for i in range(n + 1)])
    faces = [(j * (n + 1) + i, j * (n + 1) + i + 1, (j + 1) * (n + 1) + i + 1,
              (j + 1) * (n + 1) + i) for j in range(n) for i in range(n)]
    cv = np.array(faces, dtype=np.int32).ravel()
    starts = np.arange(0, len(cv), 4, dtype=np.int32)
    totals = np.full(len(faces), 4, dtype=np.int32)
    return verts, starts, totals, cv


def obj(name, mesh, rho, emission, cluster=-1, target=True):
    v, s, t, cv = mesh
    F = len(s)
    return ObjectInput(name, cluster, v, s, t, cv,
                       np.tile(np.asarray(rho, np.float32), (F, 1)),
                       np.tile(np.asarray(emission, np.float32), (F, 1)),
                       target=name if target else None)


def furnace(n=2, rho=0.5, e=1.0):
    """Closed 2-box of six inward grids."""
    s = 2.0
    sides = [((0, 0, 0), (s, 0, 0), (0, s, 0)), ((0, 0, s), (0, s, 0), (s, 0, 0)),
             ((0, 0, 0), (0, s, 0), (0, 0, s)), ((s, 0, 0), (0, 0, s), (0, s, 0)),
             ((0, 0, 0), (0, 0, s), (s, 0, 0)), ((0, s, 0), (s, 0, 0), (0, 0, s))]
    si = SceneInput()
    c = si.add_cluster("Box")
    for i, (o, u, v) in enumerate(sides):
        si.objects.append(obj(f"side{i}", grid(o, u, v, n), [rho] * 3, [e] * 3, cluster=c))
    return si


def _box(center, size):
    c, h = np.asarray(center, float), np.asarray(size, float) / 2
    verts = np.array([c + h * np.array(s) for s in
                      [(-1, -1, -1), (1, -1, -1), (1, 1, -1), (-1, 1, -1),
                       (-1, -1, 1), (1, -1, 1), (1, 1, 1), (-1, 1, 1)]])
    faces = [(0, 3, 2, 1), (4, 5, 6, 7), (0, 1, 5, 4), (1, 2, 6, 5), (2, 3, 7, 6), (3, 0, 4, 7)]
    cv = np.array(faces, dtype=np.int32).ravel()
    return verts, np.arange(0, 24, 4, dtype=np.int32), np.full(6, 4, np.int32), cv


def room(box_offset=(0.0, 0.0), light=10.0, n=6):
    """Closed inward 4x4x2 room, a light quad under the ceiling, a box in a collection.

    Each object carries ``matrix`` and object-space ``local_vertices`` as gather() fills them;
    the box's matrix is a translation by box_offset, its local geometry is fixed."""
    si = SceneInput()
    s, hgt = 4.0, 2.0
    sides = [((0, 0, 0), (0, s, 0), (s, 0, 0)), ((0, 0, hgt), (s, 0, 0), (0, s, 0)),
             ((0, 0, 0), (0, 0, hgt), (0, s, 0)), ((s, 0, 0), (0, s, 0), (0, 0, hgt)),
             ((0, 0, 0), (s, 0, 0), (0, 0, hgt)), ((0, s, 0), (0, 0, hgt), (s, 0, 0))]
    for i, (o, u, v) in enumerate(sides):
        # v x u points into the room
        si.objects.append(obj(f"wall{i}", grid(o, v, u, n), [0.6] * 3, [0, 0, 0]))
    si.objects.append(obj("light", grid((1.5, 1.5, 1.95), (0, 1, 0), (1, 0, 0), 1),
                          [0, 0, 0], [light] * 3))      # normal -z
    c = si.add_cluster("Box")
    local = _box((0, 0, 0.4), (0.8, 0.8, 0.8))
    m = np.eye(4)
    m[:3, 3] = (1.2 + box_offset[0], 1.4 + box_offset[1], 0.0)
    b = obj("box", (local[0] @ m[:3, :3].T + m[:3, 3],) + local[1:], [0.7, 0.3, 0.2], [0, 0, 0],
            cluster=c)
    b.matrix, b.local_vertices = m, local[0]
    si.objects.append(b)
    for o in si.objects:
        if o.matrix is None:
            o.matrix, o.local_vertices = np.eye(4), o.vertices
    return si


def open_floor(box_offset=(0.0, 0.0), light=10.0):
    """The Blender tests' diffuse scene (scenes.build_diffuse_scene) as arrays: a 4x4 floor
    (10x10 grid, rho 0.5), a 1x1 light 2 above it facing down, a 4x4-gridded box (rho
    0.7/0.35/0.2) in a collection, open to a black world. The box is translated by box_offset."""
    si = SceneInput()
    si.objects.append(obj("Floor", grid((-2, -2, 0), (4, 0, 0), (0, 4, 0), 10), [0.5] * 3, [0] * 3))
    si.objects.append(obj("Light", grid((-0.5, -0.5, 2.0), (0, 1, 0), (1, 0, 0), 1), [0] * 3,
                          [light] * 3))
    c = si.add_cluster("Props")
    bv, bf = gridded_box([0.6, 0.3, 0.4], [0.5, 0.5, 0.4], 4)
    local = np.array(bv)
    cv = np.array(bf, dtype=np.int32).ravel()
    nf = len(cv) // 4
    m = np.eye(4)
    m[:2, 3] = box_offset
    b = obj("Box", (local @ m[:3, :3].T + m[:3, 3], np.arange(0, len(cv), 4, dtype=np.int32),
                    np.full(nf, 4, np.int32), cv), [0.7, 0.35, 0.2], [0] * 3, cluster=c)
    b.matrix, b.local_vertices = m, local
    si.objects.append(b)
    for o in si.objects:
        if o.matrix is None:
            o.matrix, o.local_vertices = np.eye(4), o.vertices
    return si
