"""bpy-free part of the live drag's preview.

While the user drags a baked object with Live on, the real update waits until the drag pauses
(core.live.DEBOUNCE_SECONDS) and takes seconds. Each drag step meanwhile asks the kept solver
for a preview (native Solver.preview: the direct light - the object's shadow, its footprint,
the light on its own faces - re-traced at the new placement; light that bounced stays as
solved), which answers in tens of milliseconds and changes nothing of the solution. Here: which
kept objects moved, and the preview's corner patches applied to the last bake's colours.
"""
import numpy as np

from . import scene_data
from .corners import radiance_to_rgba


def unavailable(entry):
    """Why the kept solution `entry` (core.job.CachedSolution) cannot preview now, or None: it
    must exist with an idle solver, and its colours be plain radiance (not lighting-only, no
    adaptive meshes)."""
    if entry is None:
        return "no kept solution"
    if entry.in_use or entry.fingerprint is None:
        return "the kept solution is being updated"
    if not hasattr(entry.solver, "preview"):
        return "the native module has no preview"
    key = entry.settings_key or ()
    if "lighting_only" in key or "adaptive_mesh" in key:
        return "lighting-only and adaptive-mesh bakes have no preview"
    return None


def available(entry):
    return unavailable(entry) is None


def moves(entry, matrices):
    """{native object id: 4x4 relative to the build placement, as move_object takes it} for the
    kept objects whose world matrix in `matrices` ({name: 4x4}) differs from the one solved.
    A scale, shear or mirror is left out (the update bakes it in full)."""
    out = {}
    for name, m in matrices.items():
        oid = entry.object_ids.get(name)
        if oid is None or name not in entry.matrices or name not in entry.build_matrices:
            continue
        rel = scene_data.relative_move(m, entry.matrices[name], entry.build_matrices[name])
        if rel is not None and scene_data.is_rigid(rel):
            out[int(oid)] = rel
    return out


def radiance(entry, matrices):
    """({name: radiance (C,3) float32, Blender corner order} of the objects whose colours the
    preview changes, native counts). Objects not in the result show the last bake's colours."""
    mv = moves(entry, matrices)
    if not mv:
        return {}, {}
    patches, counts = entry.solver.preview(mv)
    name_of = {int(oid): name for name, oid in entry.object_ids.items()}
    index = {name: i for i, name in enumerate(entry.names)}
    out = {}
    for oid, (corners, values) in patches.items():
        name = name_of.get(int(oid))
        i = index.get(name)
        if i is None:
            continue
        rad = np.array(entry.radiance[i], dtype=np.float32, copy=True)
        perm = (entry.outputs.get(name) or {}).get("corner_perm")
        # Solver order -> Blender order (the permutation is its own inverse).
        idx = np.asarray(corners, dtype=np.int64)
        if perm is not None:
            idx = np.asarray(perm, dtype=np.int64)[idx]
        rad[idx] = values
        out[name] = rad
    return out, dict(counts)


def rgba_for(entry, name, rad):
    """The flat RGBA to write into object `name`'s mesh for radiance `rad` (its written
    corners: a modifier's corner map applied), or None when it has no write target."""
    info = entry.outputs.get(name)
    if not info or info.get("target") is None:
        return None
    cmap = info.get("corner_map")
    values = rad if cmap is None else rad[np.asarray(cmap, dtype=np.int64)]
    return radiance_to_rgba(values)


def base_radiance(entry, name):
    """The last bake's radiance of object `name` (to put back what an earlier step changed)."""
    return entry.radiance[entry.names.index(name)] if name in entry.names else None
