"""Which bake the meshes show (core.baked), read from and written to Blender data.

Each written mesh carries the bake's token in the ID property TOKEN_KEY; the records live in
memory per scene (they survive undo, which re-reads data blocks) and the newest few also in the
scene (so a saved file knows what its colours were baked with). The records in memory are the
scene's session's (core.session).
"""
import numpy as np

from .core import baked, session

TOKEN_KEY = "_radiosity_bake"       # on Mesh data; '_' keeps it out of Custom Properties
BOOK_KEY = "_bakes"                 # in scene.radiosity, beside _last_stats


def book_for(scene):
    """The scene's records: memory first, then what its file holds (after a load, or records
    an undo brought back)."""
    book = session.session(session.key_of(scene)).book
    saved = scene.radiosity.get(BOOK_KEY)
    if saved:
        book.merge(baked.RecordBook.from_json(saved))
    return book


def record(scene, token, matrices, stats):
    rec = baked.BakeRecord(token, dict(matrices), dict(stats))
    book = book_for(scene)
    book.add(rec)
    scene.radiosity[BOOK_KEY] = book.to_json()
    return rec


def mesh_tokens(view_layer):
    """{object name: token} of the visible mesh objects whose mesh carries a token."""
    out = {}
    for obj in view_layer.objects:
        if obj.type != "MESH" or obj.data is None:
            continue
        token = obj.data.get(TOKEN_KEY)
        if token is None or not obj.visible_get(view_layer=view_layer):
            continue
        out[obj.name_full] = str(token)
    return out


def judge(scene, view_layer=None):
    view_layer = view_layer or scene.view_layers[0]
    objects = {o.name_full: o for o in view_layer.objects}

    def current(name):
        obj = objects.get(name)
        if obj is None or not obj.visible_get(view_layer=view_layer):
            return None
        return np.array(obj.matrix_world, dtype=np.float64)

    return baked.judge(mesh_tokens(view_layer), book_for(scene), current)


def refresh(scene, view_layer=None):
    """Judge what the viewport shows now and hand it to the live state; returns that state."""
    st = session.session(session.key_of(scene)).live
    st.show(judge(scene, view_layer))
    return st
