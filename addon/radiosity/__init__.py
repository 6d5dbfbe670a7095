"""Radiosity for Blender: hierarchical radiosity baked into colour attributes.

Works as a legacy add-on (bl_info, Blender 3.4-4.1) and as a 4.2-5.2 extension
(blender_manifest.toml; the package is then bl_ext.<repo>.radiosity, hence relative imports only).
The compiled solver is there once per CPython version a supported Blender embeds: 3.11 (Debian's
3.4, official 4.1-5.0) and 3.13 (5.1-5.2); Python's import takes the one matching the running
Blender (bake.load_native). This file imports no bpy at module level so that the bpy-free core
(radiosity.core) can be imported by plain pytest.
"""

bl_info = {
    "name": "Radiosity",
    "author": "Radiosity for Blender developers",
    "version": (0, 1, 0),
    # The oldest Blender; bl_info has no newest one (blender_manifest.toml has, for 4.2+).
    "blender": (3, 4, 0),
    "location": "3D Viewport > Sidebar > Radiosity; Properties > Render > Radiosity",
    "description": "Bake diffuse global illumination (hierarchical radiosity) into colour "
                   "attributes",
    "category": "Render",
}


def register():
    from . import props, operators, ui, handlers
    props.register()
    operators.register()
    ui.register()
    handlers.register()


def unregister():
    from . import props, operators, ui, handlers
    handlers.unregister()
    ui.unregister()
    operators.unregister()
    props.unregister()


def pump(timeout=None):
    """Run pending live re-bakes synchronously (timers do not fire in `blender -b` scripts)."""
    from . import handlers
    return handlers.pump(timeout)


def preview_now():
    """Show a pending drag step's live preview synchronously (what the timer does)."""
    from . import handlers
    return handlers.preview_now()
