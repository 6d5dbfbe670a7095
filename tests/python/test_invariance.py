"""Scale invariance (scene units) and linearity in the emission."""
import numpy as np
import pytest

import radtest_scenes as rs


def furnished_room(rn, k=1.0, emission_scale=1.0):
    """Room (environment, coloured walls) with a one-sided ceiling lamp, a table in a
    collection and a crate in a nested collection; every length multiplied by k."""
    s = rn.Scene()
    room = rs.box([0, 0, 0], [3, 3, 2.5], 3, inward=True)
    rho = np.full((room.polygons, 3), 0.6, np.float32)
    rho[36:45] = [0.63, 0.065, 0.05]
    rho[45:54] = [0.14, 0.45, 0.091]
    ids = [room.scaled(k).add(s, "room", rho=rho)]
    ids.append(rs.square(1.5, 1.5, 2.45, 0.6, facing_up=False).scaled(k).add(
        s, "lamp", rho=0.0, emission=np.array([12.0, 11.0, 9.0]) * emission_scale, two_sided=False))
    furniture = s.add_cluster("Furniture")
    crates = s.add_cluster("Crates", furniture)
    ids.append(rs.box([0.8, 0.8, 0.6], [1.8, 1.6, 0.7], 2).scaled(k).add(s, "table", furniture, rho=[0.5, 0.35, 0.2]))
    ids.append(rs.box([2.0, 0.4, 0.2], [2.5, 0.9, 0.7], 2).scaled(k).add(s, "crate", crates, rho=[0.2, 0.4, 0.7]))
    return s, ids


def lamp_floor_wall(rn, k=1.0, emission_scale=1.0, n=8):
    """Open scene: lamp over a floor meeting a wall along an edge (the lamp shadows some
    floor-wall exchange)."""
    s = rn.Scene()
    ids = [rs.square(0, 0, 1, 1, facing_up=False).scaled(k).add(s, "lamp", rho=0.0, emission=10.0 * emission_scale,
                                                              two_sided=False)]
    ids.append(rs.square(0, 0, 0, 4, n=n).scaled(k).add(s, "floor", rho=0.5))
    ids.append(rs.grid([[-2, 2, 0], [2, 2, 0], [2, 2, 2], [-2, 2, 2]], n, n).scaled(k).add(s, "wall", rho=[0.7, 0.5, 0.3]))
    return s, ids


SCENES = {"furnished_room": furnished_room, "lamp_floor_wall": lamp_floor_wall}
_cache = {}


def solve(rn, name, preset="MEDIUM", **kw):
    key = (name, preset, tuple(sorted(kw.items())))
    if key not in _cache:
        s, ids = SCENES[name](rn, **kw)
        st = rn.Settings.preset(preset)
        # Corner points a step relative to the scene's size: Cycles' own step (the default) is
        # in world units, so it is not scale invariant, as Cycles' bake is not.
        st.cycles_corner_points = False
        solver = rn.Solver(s, st)
        solver.solve()
        _cache[key] = (np.concatenate([solver.corner_radiance(o) for o in ids]), solver.stats())
    return _cache[key]


def rel_diff(a, b):
    # Per corner and channel, relative to the reference value (floored far below the peak,
    # so exact zeros, e.g. unlit back faces, compare absolutely).
    return np.abs(a - b) / np.maximum(np.abs(b), 1e-6 * np.abs(b).max())


@pytest.mark.parametrize("name", sorted(SCENES))
@pytest.mark.parametrize("k", [1e-3, 1e3])
def test_scale_invariance(rn, name, k):
    ref, st_ref = solve(rn, name)
    got, st = solve(rn, name, k=k)
    assert got.shape == ref.shape and np.isfinite(got).all()
    d = rel_diff(got, ref)
    worst = int(d.argmax()) // 3
    assert d.max() <= 5e-3, (f"scale {k}: worst {d.max():.3%} at corner {worst} ({got[worst]} vs {ref[worst]}); "
                             f"elements {st['elements']} vs {st_ref['elements']}")


@pytest.mark.parametrize("factor", [1e-6, 1e6])
def test_linearity_in_emission(rn, factor):
    ref, st_ref = solve(rn, "furnished_room")
    got, st = solve(rn, "furnished_room", emission_scale=factor)
    assert np.isfinite(got).all()
    d = rel_diff(got / np.float32(factor), ref)
    assert d.max() <= 1e-4, f"x{factor}: worst {d.max():.2e}"
    # The relative threshold makes refinement independent of the light's intensity.
    assert st["elements"] == st_ref["elements"] and st["links"] == st_ref["links"]
