"""bpy-free state of the 'live' re-bake: transform cache, debounce and re-entry guard."""
import time

import numpy as np

DEBOUNCE_SECONDS = 0.3
MATRIX_TOLERANCE = 1e-7


class TransformCache:
    """World matrices of baked objects at their last bake, keyed by object name."""

    def __init__(self):
        self._m = {}

    def clear(self):
        self._m.clear()

    def remember(self, name, matrix):
        self._m[name] = np.array(matrix, dtype=np.float64).reshape(4, 4)

    def knows(self, name):
        return name in self._m

    def moved(self, name, matrix):
        """True when a baked object's matrix differs from the cached one (not baked -> False)."""
        old = self._m.get(name)
        if old is None:
            return False
        new = np.array(matrix, dtype=np.float64).reshape(4, 4)
        return not np.allclose(old, new, rtol=0.0, atol=MATRIX_TOLERANCE)


class LiveState:
    """One per scene key: is a re-bake pending, since when, and are we inside our own write."""

    def __init__(self):
        self.transforms = TransformCache()
        self.pending_since = None
        self.busy = False            # re-entry guard: set while we bake/write
        self.job = None              # the running asynchronous live job, if any
        self.runs = 0                # how many live re-bakes ran (tests read it)

    def request(self, now=None):
        self.pending_since = time.monotonic() if now is None else now

    @property
    def pending(self):
        return self.pending_since is not None

    def due(self, now=None, debounce=DEBOUNCE_SECONDS):
        if self.pending_since is None:
            return False
        now = time.monotonic() if now is None else now
        return now - self.pending_since >= debounce

    def take(self):
        """Consume the pending request (returns whether there was one)."""
        was = self.pending_since is not None
        self.pending_since = None
        return was


_STATES = {}


def state_for(key):
    st = _STATES.get(key)
    if st is None:
        st = _STATES[key] = LiveState()
    return st


def drop_all():
    for st in _STATES.values():
        if st.job is not None:
            try:
                st.job.cancel()
            except Exception:
                pass
    _STATES.clear()


def all_states():
    return dict(_STATES)
