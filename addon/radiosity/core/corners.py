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
# stores on the original mesh, for a moment, each vertex's and face's index in INT8 attributes
# (7-bit digits of index + 1, then check digits of a hash of the index). Blender never
# interpolates 8-bit integers, just as it never interpolates its index layer: an element a
# modifier copies or makes from an example (Mirror, Array, Solidify, Bevel's vertices around
# an original one) keeps the digits; one it interpolates from several (a subdivision's edge and
# face points) gets zeros, which decode to no original, where Blender's layer says
# ORIGINDEX_NONE. The check digits catch a modifier that mixes digits anyway.
DIGIT_BITS = 7              # 0..127 fits a signed 8-bit attribute
ORIGIN_DIGITS = 4           # index + 1 < 2^28
CHECK_DIGITS = 2
ORIGIN_HASH_BITS = 24


def origin_hash(index):
    """A bijection on [0, 2^24) that is far from linear (xor-shifts and odd multiplies): the
    check digits of a mixed element fail to match its index digits."""
    mask = (1 << ORIGIN_HASH_BITS) - 1
    x = np.asarray(index, dtype=np.int64) & mask
    for _ in range(2):
        x = ((x >> 11) ^ x) & mask
        x = (x * 0x45D9F3) & mask
    x = (x >> 11) ^ x
    return x.astype(np.int32)


def _digits(values, count):
    v = np.asarray(values, dtype=np.int64)
    return [((v >> (DIGIT_BITS * k)) & ((1 << DIGIT_BITS) - 1)).astype(np.int8)
            for k in range(count)]


def origin_digits(count):
    """The INT8 arrays (ORIGIN_DIGITS + CHECK_DIGITS of them) that encode indices 0..count-1."""
    idx = np.arange(count, dtype=np.int64)
    return _digits(idx + 1, ORIGIN_DIGITS) + _digits(origin_hash(idx), CHECK_DIGITS)


def decode_origin(digit_arrays, count):
    """Per evaluated element its original index, or -1 (all zeros: made by interpolation; check
    digits that do not match; out of range). digit_arrays: the INT8 attributes as evaluated."""
    d = [np.asarray(a, dtype=np.int64) & ((1 << DIGIT_BITS) - 1) for a in digit_arrays]
    value = sum(d[k] << (DIGIT_BITS * k) for k in range(ORIGIN_DIGITS)) - 1
    check = sum(d[ORIGIN_DIGITS + k] << (DIGIT_BITS * k) for k in range(CHECK_DIGITS))
    ok = (value >= 0) & (value < count)
    want = origin_hash(np.where(ok, value, 0)).astype(np.int64) & \
        ((1 << (DIGIT_BITS * CHECK_DIGITS)) - 1)
    return np.where(ok & (check == want), value, -1)


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


def match_in_face(corner_map, orig_totals, orig_corner_verts, orig_co, eval_totals,
                  eval_corner_verts, eval_co, eval_face_origin):
    """Fills -1 entries of corner_map whose original face has evaluated faces: with the corner
    of those faces whose vertex lies nearest the original corner's vertex. Bevel interpolates
    the attributes of the vertices it makes around an original vertex (Blender's own index
    layer copies them): the corner of the original face's shrunk copy at that vertex is the
    one Cycles takes, and the nearest. Returns the number of corners filled."""
    m = np.asarray(corner_map, dtype=np.int64)
    missing = np.nonzero(m < 0)[0]
    if not len(missing):
        return 0
    etot = np.asarray(eval_totals, dtype=np.int64)
    ecorner_face = np.asarray(eval_face_origin, dtype=np.int64)[np.repeat(np.arange(len(etot)),
                                                                           etot)]
    order = np.argsort(ecorner_face, kind="stable")      # evaluated corners by original face
    sorted_face = ecorner_face[order]
    ocv = np.asarray(orig_corner_verts, dtype=np.int64)
    oface = np.repeat(np.arange(len(orig_totals)), np.asarray(orig_totals, dtype=np.int64))
    ecv = np.asarray(eval_corner_verts, dtype=np.int64)
    eco = np.asarray(eval_co, dtype=np.float64)
    oco = np.asarray(orig_co, dtype=np.float64)
    filled = 0
    for f in np.unique(oface[missing]):
        lo, hi = np.searchsorted(sorted_face, [f, f + 1])
        if lo == hi:
            continue
        cand = order[lo:hi]                 # in evaluated order: ties go to the first
        pts = eco[ecv[cand]]
        for c in missing[oface[missing] == f]:
            d = np.einsum("ij,ij->i", pts - oco[ocv[c]], pts - oco[ocv[c]])
            m[c] = cand[int(np.argmin(d))]
            filled += 1
    corner_map[...] = m
    return filled


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
