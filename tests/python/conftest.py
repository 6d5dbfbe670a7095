"""pytest setup for the tests of the compiled module `radiosity_native`.

The module is looked for in the build tree: <repo>/build/native by default, or the
directory named by the environment variable RADIOSITY_BUILD_DIR. Nothing is skipped: if
the module cannot be imported, collection stops with an error saying where it looked.
"""
import glob
import os
import sys

import pytest

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.dirname(os.path.dirname(HERE))
BUILD_DIR = os.path.abspath(os.environ.get("RADIOSITY_BUILD_DIR") or os.path.join(REPO, "build", "native"))

if HERE not in sys.path:  # the scene helpers next to this file
    sys.path.insert(0, HERE)
if BUILD_DIR not in sys.path:
    sys.path.insert(0, BUILD_DIR)

try:
    import radiosity_native  # noqa: E402
except ImportError as exc:  # fail loudly, never skip
    found = sorted(glob.glob(os.path.join(BUILD_DIR, "radiosity_native*")))
    raise ImportError(
        "cannot import the compiled module 'radiosity_native'.\n"
        f"  looked in: {BUILD_DIR} (set RADIOSITY_BUILD_DIR to change it)\n"
        f"  files there: {found or 'none'}\n"
        f"  python: {sys.version.split()[0]} ({sys.executable}); the module must be built for this version\n"
        f"  build it with: cmake --build {os.path.join(REPO, 'build')} -j2\n"
        f"  original error: {exc}"
    ) from exc

if os.path.dirname(os.path.abspath(radiosity_native.__file__)) != BUILD_DIR:  # a stale copy elsewhere
    raise ImportError(f"imported radiosity_native from {radiosity_native.__file__}, not from the build "
                      f"directory {BUILD_DIR}: build it there or set RADIOSITY_BUILD_DIR")


def pytest_report_header(config):
    return f"radiosity_native: {radiosity_native.__file__}"


@pytest.fixture(scope="session")
def rn():
    return radiosity_native
