"""Fixture: interactive Blender 3.x+ in a 1600x1000 window under Xvfb (the window the UI problems
were reported in), binary flavour only. Tests import `run_ui_window` from here.

run_ui_window(script, *args) runs tests/blender/scripts/<script> with `--zip Z --shots DIR`
and returns its RESULT dict ("_log" holds the output). Screenshots go to DIR:
$RADIOSITY_SHOTS/<test name> when set (to look at them), else the test's tmp_path.
"""
import importlib.util
import os

import pytest


def _harness():
    """tests/blender/conftest.py's helpers. Loaded from its path under a name of its own: with
    several test folders in one pytest run, `import conftest` finds whichever came first."""
    here = os.path.dirname(os.path.abspath(__file__))
    spec = importlib.util.spec_from_file_location("radiosity_blender_harness",
                                                  os.path.join(here, "conftest.py"))
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


_h = _harness()

WINDOW = "1600x1000"


@pytest.fixture
def run_ui_window(addon_zip, tmp_path, request):
    tools = _h.window_tools()
    shots = os.environ.get("RADIOSITY_SHOTS")
    shots = os.path.join(shots, request.node.name) if shots else str(tmp_path / "shots")
    os.makedirs(shots, exist_ok=True)

    def run(script, *args):
        data = _h.run_in_window(tools, addon_zip, tmp_path, script, args, screen=WINDOW,
                                extra=("--shots", shots), stdout_tail=8000)
        data["_shots"] = shots
        return data

    return run
