"""The per-scene sessions (core.session): one object holds a scene's kept solution, live state,
bake records and saved shading, and they move, are forgotten and are dropped together."""
import pytest

from radiosity.core import baked, job, presets, session

import scenes_np


@pytest.fixture(autouse=True)
def _clean():
    session.drop_all()
    yield
    session.drop_all()


class _Run:
    """What a live state holds while a live re-bake runs (bake.BakeRun): only cancel() is used."""

    def __init__(self, fails=False):
        self.cancelled = False
        self.fails = fails

    def cancel(self):
        self.cancelled = True
        if self.fails:
            raise RuntimeError("cancel failed")


def test_a_session_is_made_once_per_key():
    a = session.session("A@1")
    assert session.session("A@1") is a
    assert session.sessions().get("B@2") is None
    assert session.kept("A@1") is None and session.kept("B@2") is None
    assert set(session.sessions()) == {"A@1"}


def test_key_of_names_scene_and_address():
    class Scene:
        name_full = "Scene"

        def as_pointer(self):
            return 0xBEEF

    assert session.key_of(Scene()) == "Scene@beef"


def test_forget_kept_leaves_the_rest():
    s = session.session("A@1")
    session.keep("A@1", "solution")
    s.live.runs = 3
    s.book.add(baked.BakeRecord("t1", {}, {}))
    s.shading[7] = ("SOLID", "MATERIAL", "STUDIO")
    session.forget_kept("A@1")
    assert session.kept("A@1") is None
    assert s.live.runs == 3 and s.book.get("t1") is not None and 7 in s.shading
    session.keep("A@1", "again")
    session.forget_kept()
    assert session.kept("A@1") is None


def test_rekey_moves_everything_and_running_jobs(native):
    s = session.session("A@1")
    session.keep("A@1", "solution")
    s.book.add(baked.BakeRecord("t1", {}, {}))
    j = job.SolveJob(native, scenes_np.furnace(2), presets.make_settings(native, "DRAFT"),
                     presets.settings_key("DRAFT", 0.05), cache_key="A@1", use_cache=False)
    session.rekey("A@1", "A@2")
    assert session.sessions().get("A@1") is None
    assert session.sessions().get("A@2") is s and session.kept("A@2") == "solution"
    assert j.cache_key == "A@2"
    # A job that finishes after the rekey keeps its solution under the new key.
    j.prepare().run()
    assert session.kept("A@2") is j.kept()


def test_rekey_onto_a_new_session_keeps_the_old_ones_state():
    old = session.session("A@1")
    session.keep("A@1", "solution")
    old.live.runs = 2
    old.book.add(baked.BakeRecord("old", {}, {}))
    new = session.session("A@2")        # made by a handler before the rekey
    new.book.add(baked.BakeRecord("new", {}, {}))
    session.rekey("A@1", "A@2")
    s = session.sessions().get("A@2")
    assert s.kept == "solution" and s.live.runs == 2
    assert s.book.get("old") is not None and s.book.get("new") is not None
    assert set(session.sessions()) == {"A@2"}


def test_drop_all_cancels_live_jobs_and_goes_on_after_a_failure():
    a, b = session.session("A@1"), session.session("B@1")
    a.live.job, b.live.job = _Run(fails=True), _Run()
    runs = (a.live.job, b.live.job)
    session.drop_all()
    assert all(r.cancelled for r in runs)
    assert session.sessions() == {}
