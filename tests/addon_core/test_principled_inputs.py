"""principled._copy_inputs without Blender: an input value the measured node cannot take is
said in the module's errors (the bake's warnings), not skipped silently."""
import importlib
import sys
import types

import pytest


class _Socket:
    def __init__(self, name, value):
        self.name, self._value = name, value

    @property
    def default_value(self):
        return self._value

    @default_value.setter
    def default_value(self, value):
        if isinstance(value, str):
            raise TypeError("expected a number")
        self._value = value


class _Inputs(list):
    def get(self, name):
        return next((s for s in self if s.name == name), None)


class _Node:
    def __init__(self, name, **values):
        self.name = name
        self.inputs = _Inputs(_Socket(k, v) for k, v in values.items())


@pytest.fixture
def principled():
    """radiosity.principled imported against stand-ins for bpy and bmesh (which _copy_inputs
    does not use), and forgotten again after the test."""
    names = ("bpy", "bmesh", "radiosity.principled", "radiosity.textures")
    saved = {n: sys.modules.pop(n) for n in names if n in sys.modules}
    package = importlib.import_module("radiosity")
    attrs = {a: getattr(package, a) for a in ("principled", "textures") if hasattr(package, a)}
    sys.modules.update({n: types.ModuleType(n) for n in ("bpy", "bmesh")})
    try:
        yield importlib.import_module("radiosity.principled")
    finally:
        for n in names:
            sys.modules.pop(n, None)
        sys.modules.update(saved)
        for a in ("principled", "textures"):
            if a in attrs:
                setattr(package, a, attrs[a])
            elif hasattr(package, a):
                delattr(package, a)


def test_an_input_that_cannot_be_copied_is_an_error(principled):
    mod = principled
    mod.pop_errors()
    src = _Node("Shiny", Roughness=0.2, IOR="odd", Metallic=0.7)
    dst = _Node("measured", Roughness=0.5, IOR=1.5, Metallic=0.0)
    mod._copy_inputs(src, dst, {"Metallic"})
    assert dst.inputs.get("Roughness").default_value == 0.2
    assert dst.inputs.get("IOR").default_value == 1.5          # kept at its default
    assert dst.inputs.get("Metallic").default_value == 0.0     # skipped
    errors = mod.pop_errors()
    assert len(errors) == 1 and "'Shiny'" in errors[0] and "'IOR'" in errors[0], errors
