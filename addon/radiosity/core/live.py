"""bpy-free state of the 'live' re-bake: transform cache, debounce, re-entry guard, and what the
viewport shows (core.baked) with what moved since."""
import time

import numpy as np

from . import baked

# A drag pauses when no move came for this long while the viewport was free to take one: a
# viewport that draws slowly handles the next step of a drag only once it has drawn this one
# (the move, its preview), seconds later, and that must not read as a pause. Only the first
# PAUSE_FRAMES frames after a move postpone the update (a viewport may never stop drawing).
DEBOUNCE_SECONDS = 0.3
PAUSE_FRAMES = 4


class TransformCache:
    """World matrices of baked objects at their last bake, keyed by object name."""

    def __init__(self):
        self._m = {}

    def clear(self):
        self._m.clear()

    def remember(self, name, matrix):
        self._m[name] = np.array(matrix, dtype=np.float64).reshape(4, 4)

    def reset(self, matrices):
        """Forget everything, then remember {name: matrix} (the bake the viewport shows)."""
        self._m.clear()
        for name, m in matrices.items():
            self.remember(name, m)

    def knows(self, name):
        return name in self._m

    def moved(self, name, matrix):
        """True when a baked object's matrix differs from the cached one (not baked -> False)."""
        old = self._m.get(name)
        if old is None:
            return False
        return not baked.same_matrix(old, matrix)


class LiveState:
    """One per scene (its session's): is a re-bake pending, since when, are we inside our own write, which
    bake the viewport shows and which of its objects moved since."""

    def __init__(self):
        # World matrices of the bake the viewport shows: the baseline moves are judged against.
        self.transforms = TransformCache()
        self.shown = baked.Shown()
        self.moved = set()           # names moved since the bake shown (depsgraph updates)
        self.pending_since = None
        self.busy = False            # re-entry guard: set while we bake/write
        self.job = None              # the running asynchronous live job, if any
        self.job_started = None      # monotonic time it started (the status text shows it)
        self.progress = 0.0          # its last polled progress, 0..1
        self.runs = 0                # how many live re-bakes ran (tests read it)
        self.failed = None           # why the last live re-bake failed, until one succeeds
        # The drag's preview (core.preview): a step waiting to be shown, how many were shown,
        # which objects show preview colours now, and what the last one did.
        self.preview_pending = False
        self.previews = 0
        self.previewed = set()
        self.last_preview = None
        self.preview_skipped = None  # why the last step was not previewed (None: it was)
        self.preview_failure_told = False  # a failed step of this drag was reported
        self.frames_since_request = 0
        # "load" or "undo" until the bake shown has been judged again: world matrices are
        # right only once the depsgraph has been evaluated after either (Blender 4+ does not
        # store them: load_post and undo_post see identity matrices for re-read objects).
        self.unjudged = None

    def show(self, shown):
        """The viewport now shows `shown` (core.baked.Shown): moves are judged against it."""
        self.unjudged = None
        self.shown = shown
        self.transforms.reset(shown.record.matrices if shown.record is not None else {})
        self.moved = set(shown.moved)

    def track(self, name, matrix):
        """A transform update of object `name`: is it away from where the bake shown has it?"""
        if not self.transforms.knows(name):
            return
        if self.transforms.moved(name, matrix):
            self.moved.add(name)
        else:
            self.moved.discard(name)

    @property
    def stale(self):
        """Why the colours shown do not fit the scene any more, or None."""
        return self.shown.reason(self.moved)

    def needs_rebake(self, name, matrix):
        """Does this transform differ from what the running live job, or else the bake shown,
        solved with? (An update that only echoes the running job's own state must not queue
        another re-bake: that one would find nothing to solve and overwrite the stats of the
        update the user watched with a cached rewrite.)"""
        base = getattr(self.job, "matrices", None) if self.job is not None else None
        if base is None:
            return self.transforms.moved(name, matrix)
        old = base.get(name)
        return old is not None and not baked.same_matrix(old, matrix)

    def request(self, now=None):
        self.pending_since = time.monotonic() if now is None else now
        self.frames_since_request = 0

    def drawn(self, now=None):
        """The viewport has drawn a frame: it could not take a move meanwhile, so the pause
        before the update counts from here (for the first PAUSE_FRAMES frames after a move)."""
        if self.pending_since is None or self.frames_since_request >= PAUSE_FRAMES:
            return
        self.frames_since_request += 1
        self.pending_since = max(self.pending_since, time.monotonic() if now is None else now)

    @property
    def pending(self):
        return self.pending_since is not None

    def due(self, now=None, debounce=DEBOUNCE_SECONDS):
        if self.pending_since is None:
            return False
        now = time.monotonic() if now is None else now
        return now - self.pending_since >= debounce

    def take(self):
        """Consume the pending request (returns whether there was one); the drag it asked an
        update for is over."""
        was = self.pending_since is not None
        self.pending_since = None
        self.preview_failure_told = False
        return was

    def preview_failed(self, why):
        """A drag step the preview could not show: keeps why; returns whether to report it (the
        first failure of a drag only: the steps after it mostly fail alike)."""
        self.preview_skipped = why
        tell = not self.preview_failure_told
        self.preview_failure_told = True
        return tell
