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


# -- in plain words (the panel) -----------------------------------------------------------------
# What a cached bake's "source" keeps of the bake that solved the colours it rewrites.
SUMMARY_KEYS = ("mode", "seconds", "live", "full_reason", "update_fallback", "moved", "added",
                "removed", "replaced", "emission_changed", "reflectance_changed",
                "texture_changed", "lights_changed", "no_emitter", "preset")

_REASONS = {
    "full bake requested": "a full bake was asked for",
    "no kept solution": "no solution was kept (first bake, file opened or solution "
                        "forgotten)",
    "settings changed": "the quality or output settings changed",
    "duplicate object names": "two objects share a name",
    "lights added, removed or changed type since the last bake":
        "lights were added, removed or changed type",
    "the kept solution is being updated by another bake":
        "another bake was updating the kept solution",
}
# The solver's reasons for solving an update in full, by the code it gives with them (stats
# "update_fallback", native stats.h UpdateFallback; its warnings word them for developers and
# may change), in the words of someone who moves furniture. Every code the module lists in
# radiosity_native.update_fallbacks has words here (tests/python/test_update_fallback.py).
FALLBACK_WORDS = {
    "pocket_moved": "an object moved into or out of a closed space (a box, a cupboard)",
    "pocket_added_removed":
        "an object added or removed opened or closed off a space (a box, a cupboard)",
    "scene_size": "objects added or removed changed the size of the whole scene more than twofold",
    "no_light": "the scene has, or had, no light",
}
_CHANGES = (("moved", "moved"), ("added", "added"), ("removed", "removed"),
            ("replaced", "changed shape"), ("emission_changed", "changed emission"),
            ("reflectance_changed", "changed colour"), ("texture_changed", "changed texture"),
            ("lights_changed", "lights changed"))


def summary(stats):
    return {k: stats[k] for k in SUMMARY_KEYS if k in stats}


def plain_reason(reason, fallback=None):
    """full_reason as a user reads it; `fallback`: the solver's code when it solved in full."""
    if fallback in FALLBACK_WORDS:
        return FALLBACK_WORDS[fallback]
    if not reason:
        return None
    text = str(reason)
    if text.startswith("the solver solved in full: "):
        text = text[len("the solver solved in full: "):]
    for tail in (": solved in full", " (solved in full)"):
        if tail in text:
            text = text.replace(tail, "")
    return _REASONS.get(text, text)


def _changes(bake):
    parts = []
    for key, words in _CHANGES:
        n = int(bake.get(key, 0) or 0)
        if n:
            parts.append(f"{n} {'object' if n == 1 else 'objects'} {words}"
                         if key != "lights_changed" else f"{n} {words}")
    return ", ".join(parts)


def describe(stats):
    """Lines for the panel: the bake that made the colours shown, in plain words, then counts.

    A cached bake solved nothing (it rewrote the kept solution's colours): the lines describe
    the bake that solved them, which its "source" keeps."""
    if not stats:
        return {"headline": None, "details": [], "counts": []}
    cached = bool(stats.get("cached"))
    bake = (stats.get("source") or stats) if cached else stats
    who = "Live update" if bake.get("live") else "Bake"
    seconds = float(bake.get("seconds", 0.0))
    details = []
    if bake.get("no_emitter"):
        headline = f"{who}: no light in the scene, {seconds:.2f} s"
        details.append("Nothing emits light: every colour is black")
    elif cached and not stats.get("source"):
        headline = f"{who}: kept colours re-written, {seconds:.2f} s"
    elif bake.get("mode") == "incremental":
        headline = f"{who}: incremental, {seconds:.2f} s"
        changed = _changes(bake)
        if changed:
            details.append(f"Changed: {changed}")
    else:
        headline = f"{who}: solved from scratch, {seconds:.2f} s"
        why = plain_reason(bake.get("full_reason"), bake.get("update_fallback"))
        if why:
            details.append(f"Why from scratch: {why}")
    if cached and stats.get("source"):
        details.append(f"Re-written from the kept solution in {float(stats.get('seconds', 0)):.2f} s")
    rays = "Rays (this update)" if bake.get("mode") == "incremental" else "Rays"
    counts = [("Objects", stats.get("objects", 0)), ("Polygons", stats.get("input_surfaces", 0)),
              ("Elements", stats.get("elements", 0)), ("Links", stats.get("links", 0)),
              (rays, stats.get("rays", 0))]
    return {"headline": headline, "details": details, "counts": counts}
