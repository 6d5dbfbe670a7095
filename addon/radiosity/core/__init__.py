"""bpy-free core of the add-on.

Everything in this package works on plain numpy arrays and dicts so that it can be unit-tested
with plain pytest (tests/addon_core) and reused by batch tools without Blender. The Blender layer
(the modules one level up) only translates bpy data into these structures and back.
"""
