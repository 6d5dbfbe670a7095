"""The `output` keyword of Scene.add_object and Solver.add_object: an object whose colours are
not read (an instance, an area light, a mesh the add-on cannot write) gets no final-gather
points, reads its leaves, and leaves every other corner as it is; and the add-on core hands the
flag over (core.scene_data)."""
import os
import sys

import numpy as np

import radtest_scenes as rs

REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))


def _room(rn, crate_output=True, crate=True):
    """A room lit by a ceiling lamp, a table, and a crate (object 3) whose output is given."""
    s = rn.Scene()
    rs.box([0, 0, 0], [3, 3, 2.5], 3, inward=True).add(s, "room", -1, rho=0.6)
    rs.square(1.5, 1.5, 2.45, 0.6, facing_up=False).add(s, "lamp", -1, rho=0.0, emission=[12, 11, 9],
                                                          two_sided=False)
    rs.box([0.8, 0.8, 0.6], [1.8, 1.6, 0.7], 2).add(s, "table", s.add_cluster("Table"), rho=[0.5, 0.35, 0.2])
    cluster = s.add_cluster("Crate")
    if crate:
        m = _crate()
        s.add_object("crate", cluster, m.vertices, m.loop_starts, m.loop_totals, m.corner_verts,
                     np.tile(np.float32([0.2, 0.4, 0.7]), (m.polygons, 1)),
                     np.zeros((m.polygons, 3), np.float32), output=crate_output)
    return s


def _crate():
    return rs.box([2.0, 0.4, 0.0], [2.5, 0.9, 0.5], 2)


def _solved(rn, scene):
    solver = rn.Solver(scene, rn.Settings.preset("DRAFT"))
    solver.solve()
    return solver


def _others(solver, n):
    return np.concatenate([solver.corner_radiance(o) for o in range(n) if o != 3])


def test_scene_output_false_gathers_nothing_there(rn):
    on = _solved(rn, _room(rn, True))
    off = _solved(rn, _room(rn, False))
    corners = _crate().corners
    st_on, st_off = on.stats(), off.stats()
    assert st_off["gather_corners"] == st_on["gather_corners"] - corners
    assert st_off["gather_points"] < st_on["gather_points"]
    c = off.corner_radiance(3)
    assert c.shape == (corners, 3)
    assert np.isfinite(c).all() and (c >= 0).all() and c.sum() > 0
    # The other objects' corners are the same, bit for bit.
    assert np.array_equal(_others(off, 4), _others(on, 4))
    # The crate still shadows the floor: the room is darker than without it.
    none = _solved(rn, _room(rn, crate=False))
    assert st_off["gather_corners"] == none.stats()["gather_corners"]
    assert off.corner_radiance(0).sum() < none.corner_radiance(0).sum()


def test_solver_add_object_takes_output(rn):
    solvers = {}
    for flag in (True, False):
        solver = _solved(rn, _room(rn, crate=False))
        m = _crate()
        oid = solver.add_object("crate", 1, m.vertices, m.loop_starts, m.loop_totals, m.corner_verts,
                                np.tile(np.float32([0.2, 0.4, 0.7]), (m.polygons, 1)),
                                np.zeros((m.polygons, 3), np.float32), output=flag)
        assert oid == 3
        solver.update()
        solvers[flag] = solver
    on, off = solvers[True], solvers[False]
    assert off.stats()["gather_corners"] == on.stats()["gather_corners"] - _crate().corners
    assert np.isfinite(off.corner_radiance(3)).all()
    assert np.array_equal(_others(off, 4), _others(on, 4))


def test_the_default_is_output(rn):
    default = _solved(rn, _room(rn, True))
    m = _crate()
    s = _room(rn, crate=False)
    s.add_object("crate", 1, m.vertices, m.loop_starts, m.loop_totals, m.corner_verts,
                 np.tile(np.float32([0.2, 0.4, 0.7]), (m.polygons, 1)), np.zeros((m.polygons, 3), np.float32))
    assert _solved(rn, s).stats()["gather_corners"] == default.stats()["gather_corners"]


def test_core_scene_data_passes_the_flag(rn):
    """core.scene_data.build_native_scene hands ObjectInput.output to the module, only when
    False; the shape digest tells the two apart (a mesh that becomes writable is replaced)."""
    sys.path.insert(0, os.path.join(REPO, "addon"))
    try:
        from radiosity.core import scene_data
    finally:
        sys.path.remove(os.path.join(REPO, "addon"))
    si = scene_data.SceneInput()
    room = rs.box([0, 0, 0], [3, 3, 2.5], 3, inward=True)
    lamp = rs.square(1.5, 1.5, 2.45, 0.6, facing_up=False)
    crate = _crate()

    def obj(name, m, rho, emission=(0, 0, 0), output=True, two_sided=None):
        return scene_data.ObjectInput(
            name=name, cluster=-1, vertices=m.vertices, loop_starts=m.loop_starts,
            loop_totals=m.loop_totals, corner_verts=m.corner_verts,
            reflectance=np.tile(np.float32(rho), (m.polygons, 1)),
            emission=np.tile(np.float32(emission), (m.polygons, 1)), output=output,
            two_sided=two_sided)

    si.objects = [obj("room", room, [0.6] * 3), obj("lamp", lamp, [0, 0, 0], [12, 11, 9],
                                                       two_sided=np.zeros(lamp.polygons, np.uint8)),
                  obj("crate", crate, [0.2, 0.4, 0.7], output=False)]
    scene, _, ids = scene_data.build_native_scene(rn, si)
    solver = _solved(rn, scene)
    assert solver.stats()["gather_corners"] == room.corners + lamp.corners
    assert np.isfinite(solver.corner_radiance(ids[2])).all()
    a = scene_data.shape_digest(si.objects[2], "")
    si.objects[2].output = True
    assert scene_data.shape_digest(si.objects[2], "") != a
