"""Fixture: interactive Blender 3.x+ in a 1600x1000 window under Xvfb (the window issue 17 was
reported in), binary flavour only. Tests import `run_ui_window` from here.

run_ui_window(script, *args) runs tests/blender/scripts/<script> with `--zip Z --shots DIR`
and returns its RESULT dict ("_log" holds the output). Screenshots go to DIR:
$RADIOSITY_SHOTS/<test name> when set (to look at them), else the test's tmp_path.
"""
import importlib.util
import json
import os
import shutil
import subprocess

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
SCRIPTS, TIMEOUT, _blender, _path_without_our_python = (
    _h.SCRIPTS, _h.TIMEOUT, _h._blender, _h._path_without_our_python)

WINDOW = "1600x1000"


@pytest.fixture
def run_ui_window(addon_zip, tmp_path, request):
    exe, why = _blender()
    if exe is None:
        pytest.skip(why)
    xvfb = shutil.which("xvfb-run")
    if xvfb is None:
        pytest.skip("xvfb-run not installed (apt-get install xvfb)")
    shots = os.environ.get("RADIOSITY_SHOTS")
    shots = os.path.join(shots, request.node.name) if shots else str(tmp_path / "shots")
    os.makedirs(shots, exist_ok=True)

    def run(script, *args):
        env = dict(os.environ)
        for var, sub in (("BLENDER_USER_CONFIG", "config"), ("BLENDER_USER_SCRIPTS", "scripts"),
                         ("BLENDER_USER_DATAFILES", "datafiles")):
            env[var] = str(tmp_path / "user" / sub)
        env["PATH"] = _path_without_our_python(env.get("PATH", ""))
        env["PYTHONPATH"] = SCRIPTS + os.pathsep + env.get("PYTHONPATH", "")
        env["PYTHONDONTWRITEBYTECODE"] = "1"
        cmd = [xvfb, "-a", "-s", f"-screen 0 {WINDOW}x24", exe, "--factory-startup",
               "--enable-event-simulate", "--python-exit-code", "1",
               "--python", os.path.join(SCRIPTS, script), "--", "--zip", addon_zip,
               "--shots", shots, *map(str, args)]
        proc = subprocess.run(cmd, capture_output=True, text=True, timeout=TIMEOUT, env=env)
        log = (f"$ {' '.join(cmd)}\n--- stdout\n{proc.stdout[-8000:]}\n--- stderr\n"
               f"{proc.stderr[-4000:]}")
        results = [l[len("RESULT "):] for l in proc.stdout.splitlines() if l.startswith("RESULT ")]
        if not results:
            pytest.fail(f"UI run gave no result (exit {proc.returncode})\n{log}")
        data = json.loads(results[-1])
        data["_log"] = log
        data["_output"] = proc.stdout + proc.stderr
        data["_shots"] = shots
        return data

    return run

