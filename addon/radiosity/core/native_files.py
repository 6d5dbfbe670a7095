"""Which compiled solver modules the installed add-on carries, and why none loaded.

The zip holds one radiosity_native per CPython version (radiosity_native.cpython-311-...so,
...-313-...); Python's import takes the one whose suffix is this interpreter's and ignores the
rest. When that fails, the user needs to know which of two things happened: the zip has no
module for this Blender's Python (wrong zip, or a Blender newer than the zip), or it has one
that could not load (a missing shared library such as Embree).
"""
import glob
import importlib.machinery
import os
import re
import sys

_VERSION = re.compile(r"\.cpython-(\d)(\d+)")


def carried(package_dir):
    """{file name: 'X.Y' or '?'} of the radiosity_native modules in package_dir."""
    out = {}
    for path in sorted(glob.glob(os.path.join(package_dir, "radiosity_native*.so"))):
        name = os.path.basename(path)
        m = _VERSION.search(name)
        out[name] = f"{m.group(1)}.{m.group(2)}" if m else "?"
    return out


def load_error(package_dir, exc, version_info=None, suffixes=None):
    """The message for a failed `from . import radiosity_native` (exc: the ImportError)."""
    vi = version_info or sys.version_info
    suffixes = suffixes if suffixes is not None else importlib.machinery.EXTENSION_SUFFIXES
    here = f"{vi[0]}.{vi[1]}"
    files = carried(package_dir)
    mine = [name for name in files if name in {"radiosity_native" + s for s in suffixes}]
    if mine:
        return (f"the native solver module for Python {here} ({mine[0]}) is installed but could "
                f"not be loaded: {exc}")
    versions = sorted({v for v in files.values() if v != "?"},
                      key=lambda v: tuple(map(int, v.split("."))))
    what = (f"the solver for Python {' and '.join(versions)} only" if versions
            else "no compiled solver")
    return (f"the native solver module could not be loaded: this Blender runs Python {here} and "
            f"the add-on carries {what}; install a radiosity.zip built with a Python {here} "
            f"module ({exc})")
