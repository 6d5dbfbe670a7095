"""What the add-on keeps for one Blender scene between bakes: one SceneSession per scene.

A session owns
  kept     the kept solution (job.CachedSolution: the native solver an incremental bake updates
           in place), or None;
  live     the live re-bake's state (live.LiveState: pending moves, the running job, previews);
  book     the record of bakes (baked.RecordBook: which bake the meshes' colours come from);
  shading  each 3D view's shading before Show Baked Colours, by the view's address.

Sessions are keyed by the caller's scene key (the Blender layer's `key_of`: the scene's name and
address). This module is the one place that makes, moves and drops them, so the four move
together: a file load drops every session, Clear and a full bake forget a kept solution, and an
undo that re-read a scene at another address moves its session to the new key (`rekey`), jobs
running for it included. Nothing here imports Blender.
"""
import traceback
import weakref

from . import baked, live


class SceneSession:
    __slots__ = ("kept", "live", "book", "shading")

    def __init__(self):
        self.kept = None
        self.live = live.LiveState()
        self.book = baked.RecordBook()
        self.shading = {}

    def take_from(self, other):
        """What `other` (the same scene under an older key) holds, in place of this session's:
        its kept solution and live state when it has them, its records merged in."""
        if other.kept is not None:
            self.kept = other.kept
        self.live = other.live
        other.book.merge(self.book)
        self.book = other.book
        self.shading.update(other.shading)


_SESSIONS = {}
# Jobs solving for a session (job.SolveJob registers itself): a rekey moves their key too, or an
# incremental job would store its updated solution under a key nobody reads any more.
_JOBS = weakref.WeakSet()


def key_of(scene):
    """A Blender scene's key: its full name and address (any object with name_full and
    as_pointer)."""
    return f"{scene.name_full}@{scene.as_pointer():x}"


def session(key):
    """The session of `key`, made empty when there is none."""
    s = _SESSIONS.get(key)
    if s is None:
        s = _SESSIONS[key] = SceneSession()
    return s


def sessions():
    """{key: session}, a copy (callers may make or drop sessions while they iterate)."""
    return dict(_SESSIONS)


def kept(key):
    """The kept solution of `key`, or None."""
    s = _SESSIONS.get(key)
    return s.kept if s is not None else None


def keep(key, entry):
    session(key).kept = entry


def forget_kept(key=None):
    """Forget the kept solution of `key` (None: of every scene); the rest of the session stays."""
    for k, s in list(_SESSIONS.items()):
        if key is None or k == key:
            s.kept = None


def drop_all():
    """Every session gone (a file was loaded: what they held belongs to the closed file); live
    jobs still running are cancelled first, and a failure to cancel is printed, not raised."""
    for s in _SESSIONS.values():
        run = s.live.job
        if run is not None:
            try:
                run.cancel()
            except Exception:   # noqa: BLE001 (a handler must go on dropping the others)
                traceback.print_exc()
    _SESSIONS.clear()


def rekey(old, new):
    """The scene of key `old` is now `new`: its session and its running jobs follow."""
    s = _SESSIONS.pop(old, None)
    if s is not None:
        there = _SESSIONS.get(new)
        if there is None:
            _SESSIONS[new] = s
        else:
            there.take_from(s)
    for job in list(_JOBS):
        if job.cache_key == old:
            job.cache_key = new


def track(job):
    _JOBS.add(job)
