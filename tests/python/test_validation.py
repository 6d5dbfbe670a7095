"""Input validation of Scene.add_object / add_cluster / Settings, zero-area polygons, n-gons."""
import math

import numpy as np
import pytest

import radtest_scenes as rs


def plate_mesh():
    return rs.grid([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]], 2, 2)  # 9 vertices, 4 quads


def add(rn, scene=None, name="obj", cluster=-1, mesh=None, rho=None, emission=None, two_sided=None, **over):
    scene = scene if scene is not None else rn.Scene()
    m = mesh or plate_mesh()
    F = m.polygons
    args = dict(vertices=m.vertices, loop_starts=m.loop_starts, loop_totals=m.loop_totals,
                corner_verts=m.corner_verts,
                reflectance=np.full((F, 3), 0.5, np.float32) if rho is None else rho,
                emission=np.zeros((F, 3), np.float32) if emission is None else emission)
    args.update(over)
    return scene.add_object(name, cluster, args["vertices"], args["loop_starts"], args["loop_totals"],
                            args["corner_verts"], args["reflectance"], args["emission"], two_sided)


def test_valid_object_is_accepted(rn):
    s = rn.Scene()
    assert add(rn, s, "a") == 0
    assert add(rn, s, "b", two_sided=np.array([True, False, True, True])) == 1
    assert s.object_count == 2
    assert s.polygon_count == 8


@pytest.mark.parametrize("bad", [math.nan, math.inf, -math.inf])
def test_non_finite_vertex_names_object_and_vertex(rn, bad):
    m = plate_mesh()
    m.vertices[3, 1] = bad
    with pytest.raises(ValueError) as e:
        add(rn, name="Suzanne.001", mesh=m)
    msg = str(e.value)
    assert "Suzanne.001" in msg and "vertex 3" in msg, msg


@pytest.mark.parametrize("value", [1.0, -0.1, math.nan, 1.5, math.inf])
def test_bad_reflectance_names_object_and_polygon(rn, value):
    rho = np.full((4, 3), 0.5, np.float32)
    rho[2, 1] = value
    with pytest.raises(ValueError) as e:
        add(rn, name="Wall", rho=rho)
    msg = str(e.value)
    assert "Wall" in msg and "polygon 2" in msg, msg


def test_reflectance_just_below_one_is_accepted(rn):
    add(rn, rho=np.full((4, 3), 0.999, np.float32))
    add(rn, rho=np.zeros((4, 3), np.float32))


@pytest.mark.parametrize("value", [-1.0, -1e-9, math.nan, math.inf])
def test_bad_emission_names_object_and_polygon(rn, value):
    em = np.zeros((4, 3))
    em[3, 0] = value
    with pytest.raises(ValueError) as e:
        add(rn, name="Lamp", emission=em)
    msg = str(e.value)
    assert "Lamp" in msg and "polygon 3" in msg, msg


@pytest.mark.parametrize("index", [9, 1000, -1])
def test_corner_index_out_of_range(rn, index):
    m = plate_mesh()
    m.corner_verts[5] = index  # the plate has 9 vertices
    with pytest.raises(ValueError) as e:
        add(rn, name="Broken", mesh=m)
    msg = str(e.value)
    assert "Broken" in msg and "corner 5" in msg, msg


def test_polygon_with_two_corners(rn):
    # A triangle, then a "polygon" of 2 corners: both use the corner array consistently.
    m = rs.Mesh(np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0]], float), np.array([0, 3], np.int32),
                np.array([3, 2], np.int32), np.array([0, 1, 2, 0, 1], np.int32))
    with pytest.raises(ValueError) as e:
        add(rn, name="Edge", mesh=m, rho=np.full((2, 3), 0.5), emission=np.zeros((2, 3)))
    msg = str(e.value)
    assert "Edge" in msg and "polygon 1" in msg, msg


def test_loops_outside_the_corner_array(rn):
    m = plate_mesh()
    m.loop_starts = m.loop_starts + 1  # the last polygon runs past the end
    with pytest.raises(ValueError) as e:
        add(rn, name="Shifted", mesh=m)
    assert "Shifted" in str(e.value) and "polygon 3" in str(e.value)


@pytest.mark.parametrize("field,value", [
    ("reflectance", np.full((3, 3), 0.5)),      # rows != polygons
    ("reflectance", np.full((5, 3), 0.5)),
    ("reflectance", np.full((4, 4), 0.5)),      # not RGB
    ("reflectance", np.full(12, 0.5)),          # flat
    ("emission", np.zeros((3, 3))),
    ("loop_totals", np.full(3, 4, np.int32)),
    ("vertices", np.zeros((9, 2))),
])
def test_mismatched_array_shapes(rn, field, value):
    with pytest.raises(ValueError) as e:
        add(rn, **{field: value})
    assert field in str(e.value), str(e.value)


def test_two_sided_length_mismatch(rn):
    with pytest.raises(ValueError):
        add(rn, two_sided=np.ones(3, bool))


@pytest.mark.parametrize("cluster", [0, 7, -2])
def test_unknown_cluster_id(rn, cluster):
    with pytest.raises(ValueError) as e:
        add(rn, name="Orphan", cluster=cluster)
    assert "Orphan" in str(e.value) and str(cluster) in str(e.value)


def test_nested_clusters(rn):
    s = rn.Scene()
    a = s.add_cluster("Furniture")
    b = s.add_cluster("Chairs", a)
    c = s.add_cluster("Chair.001", b)
    assert (a, b, c) == (0, 1, 2)
    with pytest.raises(ValueError) as e:
        s.add_cluster("Dangling", 5)
    assert "Dangling" in str(e.value)
    with pytest.raises(ValueError):
        s.add_cluster("Bad", -2)
    # Objects in the nested clusters solve and get light.
    m = rs.box([0.3, 0.3, 0.3], [0.7, 0.7, 0.7], 2)
    o1 = m.add(s, "chair", c, rho=0.5)
    o2 = rs.box([0.1, 0.1, 0.1], [0.2, 0.2, 0.2], 1).add(s, "cushion", b, rho=0.3)
    room = rs.box([0, 0, 0], [1, 1, 1], 2, inward=True).add(s, "room", -1, rho=0.5, emission=1.0)
    solver = rn.Solver(s, rn.Settings.preset("DRAFT"))
    solver.solve()
    st = solver.stats()
    assert st["clusters"] >= 4  # root + three collections (+ objects / automatic ones)
    assert st["objects"] == 3
    for o in (o1, o2, room):
        r = solver.corner_radiance(o)
        assert np.isfinite(r).all() and (r > 0).all()


def test_bad_settings_and_preset(rn):
    with pytest.raises(ValueError, match="ULTRA"):
        rn.Settings.preset("ULTRA")
    st = rn.Settings()
    st.rays_per_link = 0
    with pytest.raises(ValueError, match="rays_per_link"):
        st.validate()
    s = rn.Scene()
    add(rn, s)
    with pytest.raises(ValueError, match="rays_per_link"):
        rn.Solver(s, st)


def test_zero_area_polygons_are_skipped(rn):
    s = rn.Scene()
    rs.square(0, 0, 1, 1, facing_up=False).add(s, "lamp", rho=0.0, emission=10.0, two_sided=False)
    # Good quads plus: a collinear triangle, a quad collapsed onto one vertex, a quad folded
    # onto a line. Vertex 9 (the apex of the collinear triangle) is used by no other polygon.
    m = rs.grid([[-1, -1, 0], [1, -1, 0], [1, 1, 0], [-1, 1, 0]], 2, 2)
    v = np.vstack([m.vertices, [[0.5, -1, 0]]])
    cv = np.concatenate([m.corner_verts, [0, 9, 1], [4, 4, 4, 4], [0, 1, 1, 0]]).astype(np.int32)
    ls = np.concatenate([m.loop_starts, [16, 19, 23]]).astype(np.int32)
    lt = np.concatenate([m.loop_totals, [3, 4, 4]]).astype(np.int32)
    bad = rs.Mesh(v, ls, lt, cv)
    o = bad.add(s, "plate", rho=0.5)
    # An object made only of zero-area polygons.
    deg = rs.Mesh(np.array([[0, 0, 0.5], [1, 0, 0.5], [2, 0, 0.5]], float), np.array([0, 3], np.int32),
                  np.array([3, 3], np.int32), np.array([0, 1, 2, 2, 2, 2], np.int32))
    d = deg.add(s, "degenerate", rho=0.5)
    solver = rn.Solver(s, rn.Settings.preset("MEDIUM"))
    solver.solve()
    st = solver.stats()
    assert st["skipped_polygons"] == 5
    assert st["input_surfaces"] == 1 + 7 + 2
    r = solver.corner_radiance(o)
    assert r.shape == (bad.corners, 3)
    assert np.isfinite(r).all() and (r >= 0).all()
    assert (r[:16] > 0).all()  # the good quads are lit
    rd = solver.corner_radiance(d)
    assert rd.shape == (6, 3) and np.isfinite(rd).all() and (rd >= 0).all()


def _hexagon(r=1.0, z=0.0):
    return rs.polygon([[r * math.cos(a), r * math.sin(a), z] for a in np.arange(6) * math.pi / 3])


def _l_shape(z=0.0):
    # Concave hexagon, counter-clockwise seen from above: [-1,1]^2 without the (+,+) quadrant.
    return rs.polygon([[-1, -1, z], [1, -1, z], [1, 0, z], [0, 0, z], [0, 1, z], [-1, 1, z]])


@pytest.mark.parametrize("shape", ["hexagon", "L"])
def test_ngon_is_accepted_and_every_corner_is_lit(rn, shape):
    s = rn.Scene()
    rs.square(0, 0, 1, 1, facing_up=False).add(s, "lamp", rho=0.0, emission=10.0, two_sided=False)
    m = _hexagon() if shape == "hexagon" else _l_shape()
    o = m.add(s, shape, rho=0.5)
    solver = rn.Solver(s, rn.Settings.preset("HIGH"))
    solver.solve()
    st = solver.stats()
    assert st["input_surfaces"] == 2 and st["skipped_polygons"] == 0
    assert st["primitives"] > 2  # fan-split natively
    r = solver.corner_radiance(o)
    assert r.shape == (6, 3) and r.dtype == np.float32
    assert np.isfinite(r).all() and (r > 0).all(), r
    # Each corner's value is its leaf's, close to the analytic radiance rho*E*F at the corner
    # (leaves are small at HIGH); a wrong fan (triangles outside the polygon) would miss this.
    for c in range(6):
        x, y, _ = m.vertices[c]
        exact = 0.5 * 10 * rs.point_to_rect(x, y, -0.5, 0.5, -0.5, 0.5, 1.0)
        assert r[c, 0] == pytest.approx(exact, rel=0.10), (c, r[c, 0], exact)


def test_concave_ngon_is_symmetric(rn):
    # The L is symmetric about the diagonal x=y, as is the lamp: mirrored corners agree.
    s = rn.Scene()
    rs.square(0, 0, 1, 1, facing_up=False).add(s, "lamp", rho=0.0, emission=10.0, two_sided=False)
    o = _l_shape().add(s, "L", rho=0.5)
    solver = rn.Solver(s, rn.Settings.preset("HIGH"))
    solver.solve()
    r = solver.corner_radiance(o)[:, 0]
    assert r[1] == pytest.approx(r[5], rel=0.01)
    assert r[2] == pytest.approx(r[4], rel=0.01)


def test_radiance_at_inside_a_fan_split_ngon(rn):
    s = rn.Scene()
    rs.square(0, 0, 1, 1, facing_up=False).add(s, "lamp", rho=0.0, emission=10.0, two_sided=False)
    o = _l_shape().add(s, "L", rho=0.5)
    # Leaves fine enough that the leaf value at a point is within 10 % of the point's exact
    # radiance: a scene-wide threshold of 0.01 (HIGH's 0.05 leaves 13 % at (-0.5, 0.5)).
    st = rn.Settings.preset("HIGH")
    st.error_threshold, st.threshold_floor = 0.01, 1.0
    solver = rn.Solver(s, st)
    solver.solve()
    for x, y in [(0.9, -0.9), (0.5, -0.5), (-0.6, -0.3)]:
        a = solver.radiance_at(o, 0, [x, y, 0])[0]
        b = solver.radiance_at(o, 0, [y, x, 0])[0]  # mirror point, in another fan triangle
        exact = 0.5 * 10 * rs.point_to_rect(x, y, -0.5, 0.5, -0.5, 0.5, 1.0)
        assert a == pytest.approx(b, rel=0.02), ((x, y), a, b, exact)
        assert b == pytest.approx(exact, rel=0.10), ((y, x), b, exact)


def _pieces(n=4, face=None, pos=None, area=None, rho=None):
    """Reflectance pieces (textures.py) for plate_mesh: one per quad, at its centre."""
    f = np.arange(n, dtype=np.int32) % 4 if face is None else np.asarray(face, np.int32)
    c = np.array([[0.25, 0.25, 0], [0.75, 0.25, 0], [0.25, 0.75, 0], [0.75, 0.75, 0]])[np.arange(n) % 4]
    return (f, c if pos is None else pos, np.full(n, 0.25) if area is None else area,
            np.full((n, 3), 0.5) if rho is None else rho)


def test_texture_pieces_are_accepted_and_checked(rn):
    s = rn.Scene()
    m = plate_mesh()
    args = (m.vertices, m.loop_starts, m.loop_totals, m.corner_verts, np.full((4, 3), 0.5, np.float32),
            np.zeros((4, 3), np.float32))
    s.add_object("ok", -1, *args, pieces=_pieces())
    bad = {"missing polygon": _pieces(face=[0, 1, 2, 4]),
           "non-finite position": _pieces(pos=np.array([[0.25, 0.25, 0]] * 3 + [[np.nan, 0, 0]])),
           "area": _pieces(area=np.array([0.25, -1.0, 0.25, 0.25])),
           "reflectance outside": _pieces(rho=np.array([[0.5] * 3] * 3 + [[1.0, 0.5, 0.5]]))}
    for what, p in bad.items():
        with pytest.raises(ValueError) as e:
            s.add_object("Floor", -1, *args, pieces=p)
        assert "Floor" in str(e.value) and what in str(e.value), str(e.value)
    with pytest.raises(ValueError):
        s.add_object("Floor", -1, *args, pieces=(np.zeros(2, np.int32), np.zeros((3, 3)), np.zeros(2),
                                                  np.zeros((2, 3))))
