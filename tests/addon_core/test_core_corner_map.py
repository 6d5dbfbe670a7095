"""core.corners: evaluated corners -> original corners (modifiers), bpy-free."""
import numpy as np

from radiosity.core import corners as cc
from radiosity.core.scene_data import ObjectInput


def test_origin_digits_decode_and_mixtures_do_not():
    n = 300000
    digits = cc.origin_digits(n)
    assert all(d.dtype == np.int8 and d.min() >= 0 for d in digits)
    assert cc.decode_origin(digits, n).tolist() == list(range(n))
    # Zeros (Blender's interpolation leaves 8-bit integers at zero) decode to no original.
    assert cc.decode_origin([np.zeros(3)] * len(digits), n).tolist() == [-1] * 3
    # The rounded mean of two elements' digits (a modifier that mixes them) fails the check.
    a, b = np.arange(0, 5000), np.arange(2, 5002)
    mixed = [np.round((d[a].astype(float) + d[b]) / 2) for d in digits]
    assert (cc.decode_origin(mixed, n) == -1).mean() > 0.99
    # Out of range for the mesh: none.
    assert cc.decode_origin([d[[9]] for d in digits], 8).tolist() == [-1]


def _square():
    # one quad 0-1-2-3
    return [0], [4], [0, 1, 2, 3], 4


def test_subdivided_quad_maps_each_corner_to_its_vertex():
    starts, totals, cv, nv = _square()
    # A quad split in four (as a subdivision): new vertices 4..8 are interpolated (-1).
    # Faces: (0,4,8,7) (4,1,5,8) (8,5,2,6) (7,8,6,3), all from original face 0.
    ecv = [0, 4, 8, 7, 4, 1, 5, 8, 8, 5, 2, 6, 7, 8, 6, 3]
    vorig = [0, 1, 2, 3, -1, -1, -1, -1, -1]
    m = cc.original_corner_map(starts, totals, cv, nv, [4, 4, 4, 4], ecv, [0, 0, 0, 0], vorig)
    assert m.tolist() == [0, 5, 10, 15]


def test_first_match_wins_and_other_faces_do_not_match():
    # Two original quads sharing an edge; an evaluated copy of the mesh (Array/Mirror) repeats
    # both: the first copy's corners win.
    starts, totals, cv = [0, 4], [4, 4], [0, 1, 4, 3, 1, 2, 5, 4]
    ecv = cv + [v + 6 for v in cv]
    vorig = list(range(6)) * 2
    m = cc.original_corner_map(starts, totals, cv, 6, [4, 4, 4, 4], ecv, [0, 1, 0, 1], vorig)
    assert m.tolist() == list(range(8))
    # The copy alone (first copy dropped): the second copy's corners.
    m2 = cc.original_corner_map(starts, totals, cv, 6, [4, 4], ecv[8:], [0, 1],
                                [-1] * 6 + list(range(6)))
    assert m2.tolist() == list(range(8))
    # A face that maps to face 1 cannot give vertex 0 (not a corner of face 1).
    m3 = cc.original_corner_map(starts, totals, cv, 6, [4], [0, 1, 4, 3], [1], list(range(6)))
    assert m3.tolist() == [-1, -1, -1, -1, 1, -1, -1, 2]


def test_unmatched_corners_take_the_nearest_vertex():
    m = np.array([3, -1, 0, -1])
    n = cc.fill_unmatched(m, [0, 1, 2, 3], [-1, 2, -1, 0], [5, 4, 2, 0, 2])
    assert n == 2
    assert m.tolist() == [3, 2, 0, 3]


def test_object_input_writes_through_the_map():
    o = ObjectInput("o", -1, np.zeros((3, 3)), np.array([0]), np.array([3]),
                    np.array([0, 1, 2]), np.zeros((1, 3), np.float32),
                    np.zeros((1, 3), np.float32), corner_map=np.array([2, 2, 0, 1]))
    vals = np.array([[1.0] * 3, [2.0] * 3, [3.0] * 3])
    assert o.written_corner_count == 4
    assert o.written_values(vals)[:, 0].tolist() == [3.0, 3.0, 1.0, 2.0]


def test_bevelled_corners_take_the_nearest_corner_of_their_face():
    # Original quad 0-1-2-3 (unit square); the evaluated quad of face 0 is shrunk (vertices
    # 4..7, interpolated: no vertex origin), and a strip face (face origin 0 too) comes after.
    oco = [(0, 0, 0), (1, 0, 0), (1, 1, 0), (0, 1, 0)]
    eco = [(0, 0, 0)] * 4 + [(0.1, 0.1, 0), (0.9, 0.1, 0), (0.9, 0.9, 0), (0.1, 0.9, 0),
                             (0.1, -0.1, 0), (0.9, -0.1, 0)]
    ecv = [4, 5, 6, 7, 8, 9, 5, 4]
    m = np.full(4, -1)
    n = cc.match_in_face(m, [4], [0, 1, 2, 3], oco, [4, 4], ecv, eco, [0, 0])
    assert n == 4 and m.tolist() == [0, 1, 2, 3]
