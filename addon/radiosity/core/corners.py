"""Per-corner colour assembly: native radiance (C,3) -> flat RGBA for foreach_set."""
import numpy as np


def radiance_to_rgba(radiance, corner_count=None):
    """Flat float32 RGBA (C*4,), alpha 1, ready for ``attr.data.foreach_set("color", ...)``.

    Raises ValueError if the array has the wrong shape or holds NaN/inf: writing those into a
    mesh would be "garbage written silently", which the contract forbids.
    """
    rad = np.asarray(radiance, dtype=np.float32)
    if rad.ndim != 2 or rad.shape[1] != 3:
        raise ValueError(f"radiance must have shape (C, 3), got {rad.shape}")
    if corner_count is not None and rad.shape[0] != corner_count:
        raise ValueError(f"radiance has {rad.shape[0]} corners, mesh has {corner_count}")
    if not np.isfinite(rad).all():
        raise ValueError("solver returned non-finite radiance")
    rgba = np.ones((rad.shape[0], 4), dtype=np.float32)
    rgba[:, :3] = rad
    return rgba.ravel()


def reverse_polygon_permutation(loop_starts, loop_totals):
    """Corner permutation that reverses the winding of every polygon.

    Used for objects whose world matrix mirrors (negative determinant): transforming the vertices
    alone would flip the geometric normal, while Blender and Cycles keep the normal pointing to the
    same visible side. ``perm[i]`` is the original corner placed at new position ``i``; it is its
    own inverse, so ``out[perm] = values`` and ``values[perm]`` both map between the orders.
    """
    starts = np.asarray(loop_starts, dtype=np.int64)
    totals = np.asarray(loop_totals, dtype=np.int64)
    count = int(totals.sum())
    poly_of_corner = np.repeat(np.arange(len(starts)), totals)
    k = np.arange(count, dtype=np.int64) - np.repeat(starts, totals)
    # Keep corners in the same polygon block: start + (total - 1 - k).
    return (starts[poly_of_corner] + totals[poly_of_corner] - 1 - k).astype(np.int64)


# -- evaluated mesh -> original mesh (modifiers) ------------------------------------------------
# Blender's original-index layers (CD_ORIGINDEX) are not readable from Python. The Blender layer
# stores on the original mesh, for a moment, each vertex's and face's index twice: as is and
# hashed (INT attributes). An evaluated element copied from one original element keeps both, so
# the hash still matches; one a modifier interpolated from several (a subdivision's edge and face
# points) gets a rounded weighted mean of each, which fails the hash: such an element has no
# original, exactly where Blender's own layer says ORIGINDEX_NONE.
ORIGIN_HASH_BITS = 24       # the hashes stay exact through float32 interpolation weights


def origin_hash(index):
    """The hashed copy of an index (int32): a bijection on [0, 2^24) that is far from linear
    (xor-shifts and odd multiplies), so the rounded mean of two hashes is not the hash of the
    rounded mean of their indices (an affine hash fails exactly there: the midpoint of
    vertices 0 and 2 would pass for vertex 1)."""
    mask = (1 << ORIGIN_HASH_BITS) - 1
    x = np.asarray(index, dtype=np.int64) & mask
    for _ in range(2):
        x = ((x >> 11) ^ x) & mask
        x = (x * 0x45D9F3) & mask
    x = (x >> 11) ^ x
    return x.astype(np.int32)


def decode_origin(ids, hashes, count):
    """Per evaluated element its original index, or -1 where the pair does not match (an
    interpolated element) or is out of range. ids, hashes: the INT attributes as evaluated."""
    ids = np.asarray(ids, dtype=np.int64)
    ok = (ids >= 0) & (ids < count) & (np.asarray(hashes, np.int64) == origin_hash(
        np.clip(ids, 0, None)))
    return np.where(ok, ids, -1)


def original_corner_map(orig_starts, orig_totals, orig_corner_verts, orig_vertex_count,
                        eval_totals, eval_corner_verts, eval_face_origin, eval_vertex_origin):
    """Per corner of the original mesh, the evaluated corner whose value it takes (-1: none).

    As Cycles' "Bake to Color Attributes" maps an evaluated corner back: to the corner of its
    face's original face that holds its vertex's original vertex; the first evaluated corner in
    evaluated order (faces in order, corners in order within a face: the order of Blender's
    triangles for triangles and quads) wins. eval_face_origin / eval_vertex_origin: per
    evaluated face / vertex its original index or -1 (decode_origin)."""
    orig_totals = np.asarray(orig_totals, dtype=np.int64)
    ocv = np.asarray(orig_corner_verts, dtype=np.int64)
    nv = max(int(orig_vertex_count), 1)
    out = np.full(len(ocv), -1, dtype=np.int64)
    if not len(ocv):
        return out
    okey = np.repeat(np.arange(len(orig_totals), dtype=np.int64), orig_totals) * nv + ocv
    order = np.argsort(okey, kind="stable")     # equal keys (a repeated vertex): first corner
    skeys = okey[order]
    etot = np.asarray(eval_totals, dtype=np.int64)
    face = np.asarray(eval_face_origin, dtype=np.int64)[np.repeat(np.arange(len(etot)), etot)]
    vert = np.asarray(eval_vertex_origin, dtype=np.int64)[np.asarray(eval_corner_verts,
                                                                     dtype=np.int64)]
    ekey = face * nv + vert
    pos = np.clip(np.searchsorted(skeys, ekey), 0, len(skeys) - 1)
    hit = np.nonzero((face >= 0) & (vert >= 0) & (vert < nv) & (skeys[pos] == ekey))[0]
    target = order[pos[hit]]
    firsts, where = np.unique(target, return_index=True)    # first hit in evaluated order
    out[firsts] = hit[where]
    return out


def fill_unmatched(corner_map, orig_corner_verts, nearest_eval_vertex, eval_corner_verts):
    """Fills the -1 entries of corner_map with the first evaluated corner of the evaluated
    vertex nearest to the original corner's vertex (nearest_eval_vertex: per original vertex,
    or -1 when unknown). Returns the number of corners filled this way."""
    m = np.asarray(corner_map, dtype=np.int64)
    missing = np.nonzero(m < 0)[0]
    if not len(missing):
        return 0
    ecv = np.asarray(eval_corner_verts, dtype=np.int64)
    first_corner = np.full(int(ecv.max()) + 1 if len(ecv) else 0, -1, dtype=np.int64)
    verts, first = np.unique(ecv, return_index=True)
    first_corner[verts] = first
    near = np.asarray(nearest_eval_vertex, dtype=np.int64)[
        np.asarray(orig_corner_verts, dtype=np.int64)[missing]]
    ok = (near >= 0) & (near < len(first_corner))
    m[missing[ok]] = first_corner[near[ok]]
    corner_map[...] = m
    return int(len(missing))
