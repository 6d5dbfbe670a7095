"""Harness: run a script inside real Blender, either flavour.

Flavours (env RADIOSITY_BLENDER_FLAVOURS, comma list, default "binary,module,module313"):
  binary    - `$BLENDER (default: blender) -b --factory-startup --python-exit-code 1 --python S -- ARGS`
              (Debian's Blender 3.4, Python 3.11)
  module    - `$RADIOSITY_BPY_PYTHON (default: python3) S -- ARGS` with the PyPI `bpy` module
              (bpy 5.0, Python 3.11)
  module313 - the same in CPython 3.13 (`$RADIOSITY_BPY313_PYTHON`, else what
              scripts/find_python.sh 3.13 finds; bpy 5.2 LTS): any moduleXYZ means Python X.YZ.
A flavour that is not installed is skipped with the reason, or fails the test when
RADIOSITY_REQUIRE_FLAVOURS=1 (CI: a flavour that quietly stopped running is a failure there).

The add-on zip: $RADIOSITY_ZIP, else <repo>/build/radiosity.zip. Without one, and only when
RADIOSITY_FAKE_NATIVE=1, a zip is made from addon/radiosity plus the pure-numpy stand-in
tests/addon_core/fake_native (plumbing checks only; numeric checks skip on it).
"""
import functools
import json
import os
import re
import shutil
import subprocess
import sys
import zipfile

import pytest

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.dirname(os.path.dirname(HERE))
SCRIPTS = os.path.join(HERE, "scripts")
FLAVOURS = [f.strip() for f in os.environ.get("RADIOSITY_BLENDER_FLAVOURS",
                                              "binary,module,module313").split(",") if f.strip()]
TIMEOUT = float(os.environ.get("RADIOSITY_TEST_TIMEOUT", "900"))


def _flavour_python(flavour):
    """(interpreter, None) for a module flavour, or (None, why not)."""
    if flavour == "module":
        py = os.environ.get("RADIOSITY_BPY_PYTHON", "python3")
        exe = shutil.which(py)
        return (exe, None) if exe else (None, f"{py} not found")
    digits = flavour[len("module"):]
    version = f"{digits[0]}.{digits[1:]}"
    py = os.environ.get(f"RADIOSITY_BPY{digits}_PYTHON")
    if py:
        exe = shutil.which(py)
        return (exe, None) if exe else (None, f"{py} not found")
    r = subprocess.run(["bash", os.path.join(REPO, "scripts", "find_python.sh"), version],
                       capture_output=True, text=True, timeout=60)
    if r.returncode != 0:
        return None, f"no CPython {version} (scripts/find_python.sh {version})"
    return r.stdout.strip(), None


@functools.lru_cache(None)
def _bpy_python(flavour):
    exe, why = _flavour_python(flavour)
    if exe is None:
        return None, why
    r = subprocess.run([exe, "-c", "import bpy, sys; print(bpy.app.version_string)"],
                       capture_output=True, text=True, timeout=300)
    if r.returncode != 0:
        return None, f"`{exe} -c 'import bpy'` failed: {r.stderr.strip()[-300:]}"
    return exe, r.stdout.strip()


@functools.lru_cache(None)
def _blender():
    exe = shutil.which(os.environ.get("BLENDER", "blender"))
    return (exe, None) if exe else (None, "no blender binary on PATH (set $BLENDER)")


def _unavailable(why):
    if os.environ.get("RADIOSITY_REQUIRE_FLAVOURS") == "1":
        pytest.fail(f"{why} (RADIOSITY_REQUIRE_FLAVOURS=1)")
    pytest.skip(why)


def flavour_command(flavour):
    """(argv prefix before the script path's args) or pytest.skip."""
    if flavour == "binary":
        exe, why = _blender()
        if exe is None:
            _unavailable(why)
        return lambda script: [exe, "-b", "--factory-startup", "--python-exit-code", "1",
                               "--python", script]
    if re.fullmatch(r"module(\d\d+)?", flavour):
        exe, info = _bpy_python(flavour)
        if exe is None:
            _unavailable(f"bpy {flavour} flavour unavailable: {info}")
        return lambda script: [exe, script]
    raise ValueError(flavour)


def _path_without_our_python(path):
    """PATH minus the directories of the Python running pytest (e.g. pyenv's).

    A Blender that uses the system Python derives its Python prefix from the `python3` found on
    PATH; launched from a pyenv interpreter it would otherwise pick pyenv's stdlib and lose the
    system numpy."""
    ours = {os.path.join(p, "bin") for p in (sys.prefix, sys.base_prefix) if p != "/usr"}
    keep = [d for d in path.split(os.pathsep)
            if d and d not in ours and "/.pyenv/" not in d + "/"]
    return os.pathsep.join(keep)


def _fake_zip(tmp_dir):
    out = os.path.join(tmp_dir, "radiosity-fake.zip")
    src = os.path.join(REPO, "addon", "radiosity")
    with zipfile.ZipFile(out, "w") as z:
        for root, dirs, files in os.walk(src):
            dirs[:] = [d for d in dirs if d != "__pycache__"]
            for f in files:
                if f.endswith((".py", ".toml")):
                    full = os.path.join(root, f)
                    z.write(full, os.path.join("radiosity", os.path.relpath(full, src)))
        z.write(os.path.join(REPO, "tests", "addon_core", "fake_native", "radiosity_native.py"),
                "radiosity/radiosity_native.py")
    return out


@pytest.fixture(scope="session")
def addon_zip(tmp_path_factory):
    path = os.environ.get("RADIOSITY_ZIP") or os.path.join(REPO, "build", "radiosity.zip")
    if os.path.exists(path):
        return os.path.abspath(path)
    if os.environ.get("RADIOSITY_FAKE_NATIVE") == "1":
        return _fake_zip(str(tmp_path_factory.mktemp("fakezip")))
    pytest.skip(f"no add-on zip at {path}: build it (cmake --build build) or set RADIOSITY_ZIP")


@pytest.fixture(params=FLAVOURS)
def run_blender(request, addon_zip, tmp_path):
    """run_blender(script, *args) -> the RESULT dict printed by the script."""
    make = flavour_command(request.param)

    def run(script, *args, expect_ok=True, blend=None, raw=False):
        """raw=True: no --zip/--tmp args and the script path is taken as given (batch tool);
        blend: a .blend to open (binary: file argument; module: the script's --file)."""
        env = dict(os.environ)
        # Private user dirs: installing the add-on never touches the developer's Blender config.
        for var, sub in (("BLENDER_USER_CONFIG", "config"), ("BLENDER_USER_SCRIPTS", "scripts"),
                         ("BLENDER_USER_DATAFILES", "datafiles"),
                         ("BLENDER_USER_EXTENSIONS", "extensions")):
            env[var] = str(tmp_path / "user" / sub)
        if request.param == "binary":
            env["PATH"] = _path_without_our_python(env.get("PATH", ""))
        env["PYTHONPATH"] = SCRIPTS + os.pathsep + env.get("PYTHONPATH", "")
        env["PYTHONDONTWRITEBYTECODE"] = "1"
        path = script if raw else os.path.join(SCRIPTS, script)
        ours = [] if raw else ["--zip", addon_zip, "--tmp", str(tmp_path)]
        cmd = make(path)
        if blend is not None:
            if request.param == "binary":
                cmd.insert(cmd.index("--python"), blend)   # blender -b FILE --python S
            else:
                ours += ["--file", blend]
        cmd += ["--", *ours, *map(str, args)]
        proc = subprocess.run(cmd, capture_output=True, text=True, timeout=TIMEOUT, env=env)
        log = f"$ {' '.join(cmd)}\n--- stdout\n{proc.stdout[-6000:]}\n--- stderr\n{proc.stderr[-4000:]}"
        results = [l[len("RESULT "):] for l in proc.stdout.splitlines() if l.startswith("RESULT ")]
        if expect_ok and (proc.returncode != 0 or not results):
            pytest.fail(f"{request.param} run failed (exit {proc.returncode})\n{log}")
        data = json.loads(results[-1]) if results else {}
        data["_log"] = log
        data["_stdout"] = proc.stdout
        data["_returncode"] = proc.returncode
        data["_flavour"] = request.param
        return data

    run.flavour = request.param
    run.tmp_path = tmp_path
    run.addon_zip = addon_zip
    return run


def window_tools():
    """(blender, xvfb-run) for a Blender with its window under Xvfb; skips without either."""
    exe, why = _blender()
    if exe is None:
        pytest.skip(why)
    xvfb = shutil.which("xvfb-run")
    if xvfb is None:
        pytest.skip("xvfb-run not installed (apt-get install xvfb)")
    return exe, xvfb


def run_in_window(tools, addon_zip, tmp_path, script, args, screen="1280x1024", extra=(), stdout_tail=6000):
    """Runs tests/blender/scripts/SCRIPT in Blender's window under Xvfb (private user dirs, the
    add-on zip, `extra` and `args` after --) and returns its last RESULT line as a dict, with
    "_log" (the command and the output's tails) and "_output" (all of it)."""
    exe, xvfb = tools
    env = dict(os.environ)
    for var, sub in (("BLENDER_USER_CONFIG", "config"), ("BLENDER_USER_SCRIPTS", "scripts"),
                     ("BLENDER_USER_DATAFILES", "datafiles")):
        env[var] = str(tmp_path / "user" / sub)
    env["PATH"] = _path_without_our_python(env.get("PATH", ""))
    env["PYTHONPATH"] = SCRIPTS + os.pathsep + env.get("PYTHONPATH", "")
    env["PYTHONDONTWRITEBYTECODE"] = "1"
    cmd = [xvfb, "-a", "-s", f"-screen 0 {screen}x24", exe, "--factory-startup",
           "--enable-event-simulate", "--python-exit-code", "1",
           "--python", os.path.join(SCRIPTS, script), "--", "--zip", addon_zip,
           *extra, *map(str, args)]
    proc = subprocess.run(cmd, capture_output=True, text=True, timeout=TIMEOUT, env=env)
    log = (f"$ {' '.join(cmd)}\n--- stdout\n{proc.stdout[-stdout_tail:]}\n--- stderr\n"
           f"{proc.stderr[-4000:]}")
    results = [l[len("RESULT "):] for l in proc.stdout.splitlines() if l.startswith("RESULT ")]
    if not results:
        pytest.fail(f"UI run gave no result (exit {proc.returncode})\n{log}")
    data = json.loads(results[-1])
    data["_log"] = log
    data["_output"] = proc.stdout + proc.stderr
    return data


@pytest.fixture
def run_blender_ui(addon_zip, tmp_path):
    """Interactive Blender 3.x+ under Xvfb (modal operator, Esc, undo). Binary flavour only."""
    tools = window_tools()

    def run(script, *args):
        return run_in_window(tools, addon_zip, tmp_path, script, args)

    return run
