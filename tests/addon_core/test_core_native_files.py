"""The message a bake gives when the zip has no solver for this Blender's Python."""
from radiosity.core import native_files


def _touch(d, *names):
    for n in names:
        (d / n).write_bytes(b"")


def test_lists_versions_the_zip_carries(tmp_path):
    _touch(tmp_path, "radiosity_native.cpython-311-x86_64-linux-gnu.so",
           "radiosity_native.cpython-313-x86_64-linux-gnu.so", "bake.py")
    assert native_files.carried(str(tmp_path)) == {
        "radiosity_native.cpython-311-x86_64-linux-gnu.so": "3.11",
        "radiosity_native.cpython-313-x86_64-linux-gnu.so": "3.13"}
    msg = native_files.load_error(str(tmp_path), ImportError("cannot import name"),
                                  version_info=(3, 14, 0),
                                  suffixes=[".cpython-314-x86_64-linux-gnu.so", ".abi3.so", ".so"])
    assert "Python 3.14" in msg and "Python 3.11 and 3.13 only" in msg, msg


def test_old_zip_with_one_module(tmp_path):
    _touch(tmp_path, "radiosity_native.cpython-311-x86_64-linux-gnu.so")
    msg = native_files.load_error(str(tmp_path), ImportError("x"), version_info=(3, 13, 0),
                                  suffixes=[".cpython-313-x86_64-linux-gnu.so", ".so"])
    assert "runs Python 3.13" in msg and "Python 3.11 only" in msg, msg


def test_module_present_but_broken(tmp_path):
    """A matching module that fails (e.g. libembree3.so missing) is not a 'wrong zip'."""
    _touch(tmp_path, "radiosity_native.cpython-313-x86_64-linux-gnu.so")
    msg = native_files.load_error(str(tmp_path), ImportError("libembree3.so.3: cannot open"),
                                  version_info=(3, 13, 0),
                                  suffixes=[".cpython-313-x86_64-linux-gnu.so", ".so"])
    assert "is installed but could not be loaded" in msg and "libembree3" in msg, msg


def test_no_module_at_all(tmp_path):
    msg = native_files.load_error(str(tmp_path), ImportError("x"), version_info=(3, 11, 2),
                                  suffixes=[".cpython-311-x86_64-linux-gnu.so", ".so"])
    assert "no compiled solver" in msg, msg
