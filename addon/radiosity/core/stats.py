"""The ``last_stats`` JSON written after every bake (keys fixed by CONTRACT.md)."""
import json

MODES = ("full", "incremental")
# Integer counters the contract requires; taken from the native stats() dict, missing -> 0.
COUNT_KEYS = (
    "input_surfaces", "objects", "clusters", "elements", "links", "cluster_links",
    "obj_env_links", "env_env_links", "env_env_links_recomputed", "rays",
)
REQUIRED_KEYS = ("mode", "seconds") + COUNT_KEYS


def _as_int(value):
    try:
        return int(value)
    except (TypeError, ValueError):
        return 0


def make_stats(mode, seconds, native_stats=None, fallback=None, extra=None):
    """Build the stats dict.

    native_stats: solver.stats(); fallback: counts the add-on knows itself (objects, clusters,
    input_surfaces) used only where the native dict lacks a key; extra: additional keys (e.g.
    "cached", "preset", "warnings") that never override required ones.
    """
    if mode not in MODES:
        raise ValueError(f"mode must be one of {MODES}, got {mode!r}")
    native_stats = dict(native_stats or {})
    fallback = dict(fallback or {})
    out = {"mode": mode, "seconds": float(seconds)}
    for key in COUNT_KEYS:
        if key in native_stats:
            out[key] = _as_int(native_stats[key])
        else:
            out[key] = _as_int(fallback.get(key, 0))
    # Keep any other native numbers (solve seconds, skipped polygons, capped...) for debugging.
    for key, value in native_stats.items():
        if key not in out and isinstance(value, (bool, int, float, str)):
            out[key] = value
    for key, value in (extra or {}).items():
        if key not in REQUIRED_KEYS:
            out[key] = value
    return out


def to_json(stats):
    return json.dumps(stats, sort_keys=True)


def from_json(text):
    return json.loads(text) if text else {}
