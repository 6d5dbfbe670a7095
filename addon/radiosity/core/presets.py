"""Quality presets and their mapping onto the native Settings object."""

PRESETS = ("DRAFT", "MEDIUM", "HIGH", "CUSTOM")
# The native module knows these by name; CUSTOM is MEDIUM with the user's error threshold.
NATIVE_PRESETS = ("DRAFT", "MEDIUM", "HIGH")
CUSTOM_BASE = "MEDIUM"
DEFAULT_ERROR_THRESHOLD = 0.1  # MEDIUM's (native/src/settings.cpp)


def check_preset(name):
    if name not in PRESETS:
        raise ValueError(f"unknown preset {name!r}; expected one of {', '.join(PRESETS)}")
    return name


def make_settings(native, preset, error_threshold=DEFAULT_ERROR_THRESHOLD):
    """Return a native Settings for the preset (CUSTOM: MEDIUM + error_threshold)."""
    check_preset(preset)
    if preset == "CUSTOM":
        settings = native.Settings.preset(CUSTOM_BASE)
        if not error_threshold > 0.0:
            raise ValueError(f"error threshold must be > 0, got {error_threshold}")
        settings.error_threshold = float(error_threshold)
    else:
        settings = native.Settings.preset(preset)
    return settings


def settings_key(preset, error_threshold):
    """What identifies the discretisation for the solution cache.

    The threshold only matters for CUSTOM; for the named presets it is ignored so that touching
    the (hidden) threshold field does not invalidate a cached solution.
    """
    check_preset(preset)
    if preset == "CUSTOM":
        return ("CUSTOM", round(float(error_threshold), 12))
    return (preset,)
