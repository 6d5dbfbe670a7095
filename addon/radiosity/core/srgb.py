"""The optional byte copy for game export: radiance × 2^exposure, sRGB-encoded, clamped, 8 bits.

Pure numpy (no bpy). Blender stores a BYTE_COLOR attribute as the bytes themselves; its
``color_srgb`` property takes byte / 255, which Blender rounds back to the same byte.
"""
import numpy as np

SUFFIX = "_sRGB"      # the byte copy's attribute name: attribute_name + SUFFIX
MAX_EXPOSURE = 64.0   # stops; 2^64 keeps float64 finite for any float32 radiance


def byte_attribute_name(attribute_name):
    return attribute_name + SUFFIX


def srgb_encode(linear):
    """IEC 61966-2-1 transfer function on values in [0, 1] (float64 array)."""
    x = np.asarray(linear, dtype=np.float64)
    return np.where(x <= 0.0031308, 12.92 * x, 1.055 * np.power(np.maximum(x, 0.0031308), 1.0 / 2.4) - 0.055)


def radiance_to_srgb_bytes(radiance, exposure=0.0):
    """(C,3) linear radiance -> (C,4) uint8 RGBA: clamp(L * 2^exposure, 0, 1) encoded to sRGB,
    rounded to the nearest byte; alpha 255.

    Raises ValueError for a wrong shape, NaN/inf radiance or a non-finite exposure (garbage is
    never written).
    """
    rad = np.asarray(radiance, dtype=np.float64)
    if rad.ndim != 2 or rad.shape[1] != 3:
        raise ValueError(f"radiance must have shape (C, 3), got {rad.shape}")
    if not np.isfinite(rad).all():
        raise ValueError("solver returned non-finite radiance")
    exposure = float(exposure)
    if not np.isfinite(exposure) or abs(exposure) > MAX_EXPOSURE:
        raise ValueError(f"exposure must be a finite number of stops within ±{MAX_EXPOSURE:g}, "
                         f"got {exposure}")
    scaled = np.clip(rad * np.exp2(exposure), 0.0, 1.0)
    out = np.full((rad.shape[0], 4), 255, dtype=np.uint8)
    out[:, :3] = np.floor(srgb_encode(scaled) * 255.0 + 0.5).astype(np.uint8)
    return out


def bytes_to_color_srgb(byte_rgba):
    """Flat float32 (C*4,) for ``attr.data.foreach_set("color_srgb", ...)``."""
    return (np.asarray(byte_rgba, dtype=np.float32) / np.float32(255.0)).ravel()
