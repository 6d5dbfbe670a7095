"""Why an update solved in full reaches the add-on as a code (stats "update_fallback"), never by
the English of the solver's warning: every code the module lists has plain words in the add-on's
panel text, and a move into a closed box reports its code whatever its warning says."""
import os
import sys

import numpy as np
import radtest_scenes as rs

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(os.path.dirname(os.path.dirname(HERE)), "addon"))
from radiosity.core import stats as core_stats  # noqa: E402


def test_every_code_has_plain_words(rn):
    assert set(rn.update_fallbacks) == set(core_stats.FALLBACK_WORDS)


def _room_with_closed_box(rn):
    """A lit room, a closed box in it and a small cube beside the box (the last object)."""
    s = rn.Scene()
    rs.box([0, 0, 0], [3, 3, 2.5], 3, inward=True).add(s, "room", -1, rho=0.7)
    rs.square(1.5, 1.5, 2.4, 0.5, facing_up=False).add(s, "light", -1, rho=0.0, emission=10.0,
                                                        two_sided=False)
    rs.box([0.3, 0.3, 0.05], [1.3, 1.3, 1.05], 2).add(s, "crate", -1, rho=0.6)
    cube = rs.box([2.0, 2.0, 0.3], [2.2, 2.2, 0.5], 2).add(s, "cube", s.add_cluster("Cube"), rho=0.6)
    return s, cube


def _moved(solver, cube, by):
    m = np.eye(4)
    m[:3, 3] = by
    solver.move_object(cube, m)
    solver.update()
    return solver.stats()


def test_a_move_into_a_closed_box_gives_its_code(rn):
    s, cube = _room_with_closed_box(rn)
    solver = rn.Solver(s, rn.Settings.preset("DRAFT"))
    solver.solve()
    assert solver.stats()["update_fallback"] is None
    st = _moved(solver, cube, [-0.1, 0.0, 0.0])       # within the room: incremental
    assert st["mode"] == "incremental" and st["update_fallback"] is None
    st = _moved(solver, cube, [-1.3, -1.3, 0.0])      # into the box: solved in full
    assert st["mode"] == "full" and st["update_fallback"] == "pocket_moved", st["warnings"]
    # The panel's words come from the code alone, whatever the warning says.
    bake = {"mode": "full", "full_reason": "the solver solved in full: reworded",
            "update_fallback": st["update_fallback"]}
    assert core_stats.describe(bake)["details"] == [
        "Why from scratch: " + core_stats.FALLBACK_WORDS["pocket_moved"]]
