"""core.baked: which bake the meshes show and whether it still fits the scene."""
import numpy as np

from radiosity.core import baked
from radiosity.core import stats as core_stats
from radiosity.core.live import LiveState


def _m(x=0.0):
    m = np.eye(4)
    m[0, 3] = x
    return m


def _book(*records):
    book = baked.RecordBook()
    for r in records:
        book.add(r)
    return book


def test_fresh_moved_gone_and_older():
    a = baked.BakeRecord("a", {"Box": _m(0), "Room": _m(0)})
    b = baked.BakeRecord("b", {"Box": _m(1), "Room": _m(0)})
    book = _book(a, b)
    where = {"Box": _m(1), "Room": _m(0)}
    shown = baked.judge({"Box": "b", "Room": "b"}, book, where.get)
    assert shown.token == "b" and shown.stale is None
    # Undo put the box back but the meshes kept b's colours.
    shown = baked.judge({"Box": "b", "Room": "b"}, book, {"Box": _m(0), "Room": _m(0)}.get)
    assert shown.stale == "'Box' moved since the bake"
    # Undo re-read one mesh only: it shows a, the newest (b) is the bake shown.
    shown = baked.judge({"Box": "a", "Room": "b"}, book, where.get)
    assert shown.token == "b" and "'Box' shows the colours of an earlier bake" == shown.stale
    shown = baked.judge({"Box": "b", "Room": "b"}, book, {"Room": _m(0)}.get)
    assert shown.stale == "'Box' is gone or hidden since the bake"
    assert baked.judge({}, book, where.get).token is None
    # A token no record knows (another session's file without records): nothing to judge.
    unknown = baked.judge({"Box": "z"}, book, where.get)
    assert unknown.baked and unknown.record is None and unknown.stale is None


def test_float32_noise_is_not_a_move():
    big = _m(300.0)
    noisy = big.copy()
    noisy[0, 3] = np.float32(300.0) + np.float32(3e-5)      # one float32 ulp at 300
    assert baked.same_matrix(big, noisy)
    assert not baked.same_matrix(big, _m(300.01))


def test_book_bounded_merge_and_json():
    book = baked.RecordBook(limit=3)
    for t in "abcd":
        book.add(baked.BakeRecord(t, {"X": _m(ord(t))}, {"mode": "full"}))
    assert book.get("a") is None and book.age("d") > book.age("b") > 0
    saved = baked.RecordBook.from_json(book.to_json(newest=2))
    assert saved.get("b") is None and saved.get("c").stats == {"mode": "full"}
    assert np.allclose(saved.get("d").matrices["X"], _m(ord("d")))
    other = baked.RecordBook()
    other.add(baked.BakeRecord("old", {}))
    book.merge(other)           # full: what it merges counts as older, and goes first
    assert book.get("old") is None and book.get("b") is not None
    book.limit = 10
    book.merge(other)
    assert book.get("old") is not None and book.age("old") < book.age("b")
    assert baked.RecordBook.from_json("not json").get("x") is None


def test_live_state_tracks_moves_against_the_bake_shown():
    st = LiveState()
    st.show(baked.Shown("a", baked.BakeRecord("a", {"Box": _m(0)})))
    assert st.stale is None
    st.track("Box", _m(2))
    assert st.stale == "'Box' moved since the bake" and st.needs_rebake("Box", _m(2))
    st.track("Box", _m(0))      # moved back
    assert st.stale is None and not st.needs_rebake("Box", _m(0))
    st.track("Lamp", _m(5))     # not in the bake: ignored

    class Job:
        matrices = {"Box": _m(2)}
    st.job = Job()
    # While a job solves for x=2, an update at x=2 is its own state: no second re-bake.
    assert not st.needs_rebake("Box", _m(2)) and st.needs_rebake("Box", _m(3))


def test_panel_words():
    full = {"mode": "full", "seconds": 20.24, "cached": False, "full_reason": "no kept solution",
            "objects": 4, "input_surfaces": 3992, "elements": 1, "links": 2, "rays": 3}
    d = core_stats.describe(full)
    assert d["headline"] == "Bake: solved from scratch, 20.24 s"
    assert d["details"][0].startswith("Why from scratch: no solution was kept")
    assert ("Polygons", 3992) in d["counts"]
    live = dict(full, mode="incremental", live=True, seconds=1.84, moved=1, full_reason=None)
    d = core_stats.describe(live)
    assert d["headline"] == "Live update: incremental, 1.84 s"
    assert d["details"] == ["Changed: 1 object moved"]
    assert ("Rays (this update)", 3) in d["counts"]
    cached = dict(full, cached=True, seconds=0.79, source=core_stats.summary(live))
    d = core_stats.describe(cached)
    assert d["headline"] == "Live update: incremental, 1.84 s"
    assert d["details"][-1] == "Re-written from the kept solution in 0.79 s"
    # The solver's reason by its code (stats "update_fallback"), not by its warning's words.
    pocket = dict(full, live=True, full_reason="the solver solved in full: any words at all",
                  update_fallback="pocket_moved")
    d = core_stats.describe(pocket)
    assert d["headline"].startswith("Live update: solved from scratch")
    assert d["details"] == ["Why from scratch: an object moved into or out of a closed space "
                            "(a box, a cupboard)"]
    assert core_stats.describe({})["headline"] is None
