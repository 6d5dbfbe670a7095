"""Which bake the colours in the meshes show, and whether the scene has moved on since.

Every bake writes a new token into each mesh it colours and keeps a record under that token:
the world matrices it solved with and its stats. Blender's undo re-reads only the data blocks
an undo step changed, so after undo or redo the meshes may hold colours of one bake while the
objects stand where another left them (a live re-bake writes after the move's undo step was
pushed: undoing the move can keep those colours). The tokens the meshes carry, looked up here,
say which bake the viewport shows and whether it still fits the scene.
"""
from collections import OrderedDict
from dataclasses import dataclass, field
import json
import uuid

import numpy as np

RECORDS_KEPT = 16           # in memory: the bakes an undo history walks back through
RECORDS_SAVED = 2           # in the file: a saved file shows the newest (every record holds
                            # a matrix per object: a furnished scene's would weigh megabytes)
# Matrices are float32 in Blender: compare with a relative tolerance, or a room hundreds of
# units across would differ in its last bits after an undo re-read.
MATRIX_RTOL = 1e-6
MATRIX_ATOL = 1e-7


def new_token():
    return uuid.uuid4().hex[:16]


def same_matrix(a, b):
    a = np.asarray(a, dtype=np.float64).reshape(4, 4)
    b = np.asarray(b, dtype=np.float64).reshape(4, 4)
    return bool(np.allclose(a, b, rtol=MATRIX_RTOL, atol=MATRIX_ATOL))


@dataclass
class BakeRecord:
    token: str
    matrices: dict            # object name -> 4x4 world matrix the bake solved with
    stats: dict = field(default_factory=dict)    # that bake's last_stats

    def to_plain(self):
        return {"matrices": {n: np.asarray(m, dtype=np.float64).reshape(16).tolist()
                             for n, m in self.matrices.items()},
                "stats": self.stats}

    @classmethod
    def from_plain(cls, token, plain):
        return cls(token, {n: np.asarray(m, dtype=np.float64).reshape(4, 4)
                           for n, m in plain.get("matrices", {}).items()},
                   dict(plain.get("stats", {})))


class RecordBook:
    """Records by token, oldest first, bounded."""

    def __init__(self, limit=RECORDS_KEPT):
        self._r = OrderedDict()
        self.limit = limit

    def add(self, record):
        self._r.pop(record.token, None)
        self._r[record.token] = record
        while len(self._r) > self.limit:
            self._r.popitem(last=False)

    def get(self, token):
        return self._r.get(token)

    def age(self, token):
        """Larger is newer; -1 for an unknown token."""
        for i, t in enumerate(reversed(self._r)):
            if t == token:
                return len(self._r) - i
        return -1

    def merge(self, other):
        """Adds records of `other` this book lacks (they count as older than its own)."""
        missing = [(t, r) for t, r in other._r.items() if t not in self._r]
        if not missing:
            return
        own = list(self._r.items())
        self._r = OrderedDict(missing + own)
        while len(self._r) > self.limit:
            self._r.popitem(last=False)

    def to_json(self, newest=RECORDS_SAVED):
        items = list(self._r.items())[-newest:]
        return json.dumps({t: r.to_plain() for t, r in items})

    @classmethod
    def from_json(cls, text, limit=RECORDS_KEPT):
        book = cls(limit)
        try:
            data = json.loads(text) if text else {}
        except ValueError:
            data = {}
        for token, plain in data.items():
            book.add(BakeRecord.from_plain(token, plain))
        return book

    def __len__(self):
        return len(self._r)


@dataclass
class Shown:
    """What the viewport shows: the bake's token and record (None when no mesh carries a token
    or the token is unknown), and where it no longer fits the scene: meshes showing an older
    bake, objects moved, objects gone or hidden since."""
    token: str = None
    record: BakeRecord = None
    older: list = field(default_factory=list)
    moved: list = field(default_factory=list)
    gone: list = field(default_factory=list)

    @property
    def baked(self):
        return self.token is not None

    def reason(self, moved=None):
        """Why the colours are out of date, or None. `moved` replaces the names moved at the
        time of judging (the live state tracks moves from depsgraph updates)."""
        moved = self.moved if moved is None else moved
        if self.older:
            n = len(self.older)
            return f"{_names(self.older)} show{'s' if n == 1 else ''} the colours of an earlier bake"
        if moved:
            return f"{_names(moved)} moved since the bake"
        if self.gone:
            return (f"{_names(self.gone)} {'is' if len(self.gone) == 1 else 'are'} gone or "
                    f"hidden since the bake")
        return None

    @property
    def stale(self):
        return self.reason()


def _names(names, limit=3):
    names = sorted(names)
    text = ", ".join(f"'{n}'" for n in names[:limit])
    return text + (f" and {len(names) - limit} more" if len(names) > limit else "")


def judge(mesh_tokens, book, current_matrix):
    """mesh_tokens: {object name: token} of the visible meshes that carry one;
    current_matrix(name): the object's world matrix now, None when it is gone or hidden.

    The newest known token is the bake shown; meshes with another token show an older bake."""
    if not mesh_tokens:
        return Shown()
    known = {t for t in mesh_tokens.values() if book.get(t) is not None}
    if not known:
        # Baked by a session whose records this file does not hold: nothing to compare with.
        return Shown(token=next(iter(mesh_tokens.values())))
    token = max(known, key=book.age)
    record = book.get(token)
    shown = Shown(token, record)
    shown.older = sorted(n for n, t in mesh_tokens.items() if t != token)
    for name, m in record.matrices.items():
        now = current_matrix(name)
        if now is None:
            shown.gone.append(name)
        elif not same_matrix(now, m):
            shown.moved.append(name)
    return shown
