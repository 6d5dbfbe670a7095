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
