"""Synchronous solve: output arrays, stats keys and their consistency, no emitter, empty scene."""
import numpy as np
import pytest

import radtest_scenes as rs

STATS_KEYS = {
    # the brief / the add-on rely on these
    "input_surfaces", "objects", "clusters", "elements", "links", "cluster_links", "obj_env_links",
    "env_env_links", "env_env_links_recomputed", "rays", "iterations", "residual", "seconds_total",
    # the rest of native/include/radiosity/stats.h
    "primitives", "skipped_polygons", "element_nodes", "surface_links", "history_links", "obj_obj_links",
    "links_evaluated", "refined_by_oracle", "avoided_by_progressive", "refine_rounds", "capped",
    "iteration_capped", "no_emitters", "seconds_build", "seconds_link", "seconds_solve", "warnings",
}
INT_KEYS = {"input_surfaces", "primitives", "skipped_polygons", "objects", "clusters", "elements", "element_nodes",
            "links", "cluster_links", "surface_links", "history_links", "obj_env_links", "env_env_links",
            "obj_obj_links", "env_env_links_recomputed", "rays", "links_evaluated", "refined_by_oracle",
            "avoided_by_progressive", "iterations", "refine_rounds"}


def room_with_furniture(rn):
    """A room (environment) lit by a ceiling lamp, a table in a collection and a crate in a
    nested collection: every link class (env-env, obj-env, obj-obj) can occur."""
    s = rn.Scene()
    meshes = {}
    room = rs.box([0, 0, 0], [3, 3, 2.5], 3, inward=True)
    rho = np.full((room.polygons, 3), 0.6, np.float32)
    rho[4 * 9:5 * 9] = [0.63, 0.065, 0.05]  # -x wall red
    rho[5 * 9:6 * 9] = [0.14, 0.45, 0.091]  # +x wall green
    ids = {"room": room.add(s, "room", -1, rho=rho)}
    meshes["room"] = room
    lamp = rs.square(1.5, 1.5, 2.45, 0.6, facing_up=False)
    ids["lamp"] = lamp.add(s, "lamp", -1, rho=0.0, emission=[12, 11, 9], two_sided=False)
    meshes["lamp"] = lamp
    furniture = s.add_cluster("Furniture")
    crates = s.add_cluster("Crates", furniture)
    table = rs.box([0.8, 0.8, 0.6], [1.8, 1.6, 0.7], 2)
    ids["table"] = table.add(s, "table", furniture, rho=[0.5, 0.35, 0.2])
    meshes["table"] = table
    crate = rs.box([2.0, 0.4, 0.2], [2.5, 0.9, 0.7], 2)
    ids["crate"] = crate.add(s, "crate", crates, rho=[0.2, 0.4, 0.7])
    meshes["crate"] = crate
    return s, ids, meshes


@pytest.fixture(scope="module")
def solved_room(rn):
    s, ids, meshes = room_with_furniture(rn)
    solver = rn.Solver(s, rn.Settings.preset("DRAFT"))
    solver.solve()
    return s, solver, ids, meshes


def test_corner_radiance_arrays(rn, solved_room):
    _, solver, ids, meshes = solved_room
    for name, o in ids.items():
        r = solver.corner_radiance(o)
        assert isinstance(r, np.ndarray)
        assert r.shape == (meshes[name].corners, 3), name
        assert r.dtype == np.float32, name
        assert r.flags.c_contiguous
        assert np.isfinite(r).all(), name
        assert (r >= 0).all(), name
    # The lamp (rho = 0) shows exactly its emission; the lit room is not black.
    np.testing.assert_allclose(solver.corner_radiance(ids["lamp"]), np.tile([12, 11, 9], (4, 1)), rtol=1e-6)
    assert solver.corner_radiance(ids["room"]).max() > 0.1
    # Returned arrays are copies: writing into one does not change the next.
    r = solver.corner_radiance(ids["room"])
    r[:] = -1
    assert (solver.corner_radiance(ids["room"]) >= 0).all()


def test_bad_object_and_face_ids(rn, solved_room):
    _, solver, ids, _ = solved_room
    with pytest.raises(IndexError):
        solver.corner_radiance(len(ids))
    with pytest.raises(IndexError):
        solver.corner_radiance(-1)
    with pytest.raises(IndexError):
        solver.radiance_at(ids["room"], 10_000, [0, 0, 0])


def test_stats_keys_and_types(rn, solved_room):
    _, solver, _, _ = solved_room
    st = solver.stats()
    assert isinstance(st, dict)
    missing = STATS_KEYS - st.keys()
    assert not missing, missing
    for k in INT_KEYS:
        assert isinstance(st[k], int) and st[k] >= 0, (k, st[k])
    for k in ("residual", "seconds_build", "seconds_link", "seconds_solve", "seconds_total"):
        assert isinstance(st[k], float) and st[k] >= 0, (k, st[k])
    for k in ("capped", "iteration_capped", "no_emitters"):
        assert isinstance(st[k], bool), k
    assert isinstance(st["warnings"], list) and all(isinstance(w, str) for w in st["warnings"])


def test_stats_are_consistent(rn, solved_room):
    scene, solver, ids, meshes = solved_room
    st = solver.stats()
    assert st["objects"] == len(ids) == scene.object_count
    assert st["input_surfaces"] == scene.polygon_count == sum(m.polygons for m in meshes.values())
    assert st["skipped_polygons"] == 0
    assert st["primitives"] == st["input_surfaces"]  # all planar convex quads
    assert st["clusters"] >= 3  # the root and the two collections at least
    assert st["links"] == st["cluster_links"] + st["surface_links"]
    assert st["links"] == st["obj_env_links"] + st["env_env_links"] + st["obj_obj_links"]
    assert st["links"] > 0 and st["env_env_links"] > 0 and st["obj_env_links"] > 0
    assert st["cluster_links"] > 0  # clustering is on by default
    assert 0 < st["elements"] <= st["element_nodes"]
    assert st["rays"] > 0 and st["iterations"] >= 1
    assert st["env_env_links_recomputed"] <= st["env_env_links"]
    assert not st["no_emitters"]
    assert st["seconds_total"] > 0
    assert st["seconds_total"] >= 0.99 * (st["seconds_build"] + st["seconds_link"] + st["seconds_solve"])
    if not st["iteration_capped"]:
        assert st["residual"] <= rn.Settings.preset("DRAFT").tolerance


def test_stats_with_clustering_off(rn):
    s, ids, _ = room_with_furniture(rn)
    st = rn.Settings.preset("DRAFT")
    st.use_clustering = False
    solver = rn.Solver(s, st)
    solver.solve()
    d = solver.stats()
    assert d["cluster_links"] == 0
    assert d["links"] == d["surface_links"] == d["obj_env_links"] + d["env_env_links"] + d["obj_obj_links"]
    for o in ids.values():
        r = solver.corner_radiance(o)
        assert np.isfinite(r).all() and (r >= 0).all()


def test_results_before_any_solve_raise(rn):
    s, ids, _ = room_with_furniture(rn)
    solver = rn.Solver(s, rn.Settings.preset("DRAFT"))
    with pytest.raises(RuntimeError, match="no finished solve"):
        solver.corner_radiance(0)
    with pytest.raises(RuntimeError, match="no finished solve"):
        solver.radiance_at(0, 0, [0, 0, 0])
    with pytest.raises(RuntimeError, match="no finished solve"):
        solver.object_costs()
    # Nor on an empty scene (the hierarchy has no root then; it crashed).
    with pytest.raises(RuntimeError, match="no finished solve"):
        rn.Solver(rn.Scene(), rn.Settings.preset("DRAFT")).object_costs()


def test_solver_copies_its_scene(rn):
    # Adding to the Scene after constructing the Solver does not affect the solver.
    s, ids, _ = room_with_furniture(rn)
    solver = rn.Solver(s, rn.Settings.preset("DRAFT"))
    rs.square(0, 0, 5, 1).add(s, "late", rho=0.5)
    solver.solve()
    assert solver.stats()["objects"] == len(ids)


def test_one_sided_emitter_lights_only_its_front(rn):
    # A lamp facing down between two plates: the plate below is lit, the one above (facing
    # down at the lamp's back) gets nothing from it.
    s = rn.Scene()
    rs.square(0, 0, 1, 1, facing_up=False).add(s, "lamp", rho=0.0, emission=10.0, two_sided=np.array([False]))
    below = rs.square(0, 0, 0, 2, n=2).add(s, "below", rho=0.5, two_sided=False)
    above = rs.square(0, 0, 2, 2, n=2, facing_up=False).add(s, "above", rho=0.5, two_sided=False)
    solver = rn.Solver(s, rn.Settings.preset("MEDIUM"))
    solver.solve()
    assert (solver.corner_radiance(below) > 0.1).all()
    # "above" sees only the lamp's back and the lit plate's light blocked by the lamp in the
    # middle: its corners get light reflected by "below" only, far less than "below".
    assert solver.corner_radiance(above).max() < 0.1 * solver.corner_radiance(below).max()


def test_no_emitter_gives_zeros_and_a_warning(rn):
    s = rn.Scene()
    o = rs.box([0, 0, 0], [1, 1, 1], 2, inward=True).add(s, "room", rho=0.5)
    p = rs.square(0.5, 0.5, 0.5, 0.3).add(s, "plate", rho=0.9)
    solver = rn.Solver(s, rn.Settings.preset("MEDIUM"))
    solver.solve()
    st = solver.stats()
    assert st["no_emitters"] is True
    assert st["warnings"], st
    assert any("emitter" in w for w in st["warnings"])
    for obj in (o, p):
        r = solver.corner_radiance(obj)
        assert r.dtype == np.float32 and np.isfinite(r).all()
        assert (r == 0).all()


def test_empty_scene(rn):
    # Observed binding behaviour: an empty scene solves (no error), reports no emitter with
    # a warning, and has no object to query.
    s = rn.Scene()
    assert s.object_count == 0 and s.polygon_count == 0
    solver = rn.Solver(s, rn.Settings.preset("MEDIUM"))
    solver.solve()
    st = solver.stats()
    assert st["objects"] == 0 and st["input_surfaces"] == 0 and st["elements"] == 0 and st["links"] == 0
    assert st["no_emitters"] is True and st["warnings"]
    with pytest.raises(IndexError):
        solver.corner_radiance(0)
    assert solver.object_costs() == []


def test_object_costs(rn, solved_room):
    """Solver.object_costs: per object, its output points' rays (they add up to the final
    gather's) and its links with the rest of the scene; links inside one object count for none."""
    scene, solver, ids, _ = solved_room
    st = solver.stats()
    costs = solver.object_costs()
    assert len(costs) == scene.object_count
    keys = {"point_rays", "links", "link_rays", "history_links", "history_link_rays"}
    for c in costs:
        assert set(c) == keys and all(isinstance(v, int) and v >= 0 for v in c.values())
    points = sum(c["point_rays"] for c in costs)
    # All of the final gather's rays but the few of its sealed-solid check belong to a point.
    assert 0.98 * st["gather_rays"] <= points <= st["gather_rays"]
    for name in ("room", "lamp", "table", "crate"):
        c = costs[ids[name]]
        assert c["links"] > 0 and c["link_rays"] > 0, name
    assert costs[ids["room"]]["point_rays"] > costs[ids["crate"]]["point_rays"] > 0
    # A link has two ends: the room's links with the rest at most all the others' together.
    others = sum(costs[ids[n]]["links"] for n in ("lamp", "table", "crate"))
    assert costs[ids["room"]]["links"] <= others

    # One object alone: every link lies inside it.
    s = rn.Scene()
    room = rs.box([0, 0, 0], [1, 1, 1], 2, inward=True)
    room.add(s, "room", -1, rho=0.5, emission=1.0)
    one = rn.Solver(s, rn.Settings.preset("DRAFT"))
    one.solve()
    (c,) = one.object_costs()
    assert c["links"] == c["history_links"] == c["link_rays"] == 0
    assert c["point_rays"] > 0


def test_object_costs_after_a_move(rn):
    """After an update the points' rays are the update's: the moved crate's points are traced
    anew, the others mostly kept or replayed."""
    s, ids, _ = room_with_furniture(rn)
    solver = rn.Solver(s, rn.Settings.preset("DRAFT"))
    solver.solve()
    before = solver.object_costs()
    m = np.eye(4)
    m[1, 3] = -0.2
    solver.move_object(ids["crate"], m)
    solver.update()
    assert solver.stats()["mode"] == "incremental"
    after = solver.object_costs()
    assert after[ids["crate"]]["point_rays"] > 0.5 * before[ids["crate"]]["point_rays"]
    assert after[ids["crate"]]["links"] > 0
    for name in ("room", "lamp", "table"):
        assert after[ids[name]]["point_rays"] < 0.5 * before[ids[name]]["point_rays"], name
