"""Plain pytest of the bpy-free core (addon/radiosity/core); no Blender involved.

`native` runs a test with the pure-numpy stand-in (fake_native/) and, when it can be imported,
with the real compiled module: $RADIOSITY_NATIVE_DIR, else build/native/, else build-addon/native/.
"""
import glob
import importlib.machinery
import importlib.util
import os
import sys

import pytest

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.dirname(os.path.dirname(HERE))
sys.path.insert(0, os.path.join(REPO, "addon"))
from radiosity.core import session  # noqa: E402


def _load(name, path):
    spec = importlib.util.spec_from_file_location("radiosity_native", path)
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


def _real_native():
    dirs = [os.environ.get("RADIOSITY_NATIVE_DIR"), os.path.join(REPO, "build", "native"),
            os.path.join(REPO, "build-addon", "native")]
    for d in filter(None, dirs):
        # The build holds one module per CPython version (cp311, cp313): take this Python's.
        for suffix in importlib.machinery.EXTENSION_SUFFIXES:
            so = os.path.join(d, "radiosity_native" + suffix)
            if not os.path.exists(so):
                continue
            try:
                return _load("radiosity_native", so), None
            except ImportError as exc:
                return None, f"{so}: {exc}"
        found = glob.glob(os.path.join(d, "radiosity_native*.so"))
        if found:
            return None, (f"no radiosity_native for Python {sys.version.split()[0]} in {d} "
                          f"(there: {', '.join(sorted(map(os.path.basename, found)))})")
    return None, "no compiled radiosity_native found (build it or set RADIOSITY_NATIVE_DIR)"


@pytest.fixture(params=["fake", "real"], scope="session")
def native(request):
    if request.param == "fake":
        return _load("radiosity_native",
                     os.path.join(HERE, "fake_native", "radiosity_native.py"))
    mod, why = _real_native()
    if mod is None:
        pytest.skip(why)
    return mod


@pytest.fixture
def no_kept_solutions():
    """No solution kept from another test before the test, none left after it."""
    session.forget_kept()
    yield
    session.forget_kept()
