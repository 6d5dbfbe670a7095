"""Launch a bench/tradeoff script in Blender, headless (used by the run_*.py drivers).

Two flavours, as in tests/blender/conftest.py:
  binary - Debian's Blender 3.4 (`blender -b FILE --python S -- ARGS`), PATH without pyenv (a
           system-Python Blender would otherwise pick pyenv's stdlib and lose the system numpy);
  bpy    - PyPI's bpy module (Blender 5.x) in $RADIOSITY_BPY_PYTHON (default: the interpreter
           running the driver, which scripts/install_deps.sh gave bpy), through
           run_in_bpy.py, which opens FILE and runs S with ARGS. Blender 3.4's Cycles reads mesh
           lamps seen at grazing angles too dark (bench/results/reference_bias.md); 5.x does not,
           so the references and the competitor are made there.
Both get private Blender user dirs (installing the add-on never touches the developer's config).
"""
import argparse
import json
import os
import shutil
import subprocess
import sys
import tempfile
import time

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.dirname(os.path.dirname(HERE))


def driver_parser(prog):
    """The argument parser of a run_NAME.py driver, holding the two options results_dir reads:
    --quick (a smoke run) and --out-dir; the driver adds its own."""
    p = argparse.ArgumentParser(prog=prog)
    p.add_argument("--quick", action="store_true")
    p.add_argument("--out-dir")
    return p


def results_dir(given, quick, name):
    """Where a run_NAME.py driver writes: --out-dir (`given`), else for --quick a new temporary
    directory (a smoke run never writes over the committed results), else bench/results."""
    return given or (tempfile.mkdtemp(prefix=f"{name}-quick-") if quick
                     else os.path.join(REPO, "bench", "results"))


def data_dir(out_dir, name):
    """The driver's folder of per-scene JSON and logs in `out_dir` (NAME_data), made."""
    path = os.path.join(out_dir, f"{name}_data")
    os.makedirs(path, exist_ok=True)
    return path


def path_without_pyenv(path):
    ours = {os.path.join(p, "bin") for p in (sys.prefix, sys.base_prefix) if p != "/usr"}
    return os.pathsep.join(d for d in path.split(os.pathsep)
                           if d and d not in ours and "/.pyenv/" not in d + "/")


def blender_exe():
    exe = shutil.which(os.environ.get("BLENDER", "blender"),
                       path=path_without_pyenv(os.environ.get("PATH", "")))
    if exe is None:
        raise SystemExit("no blender binary on PATH (set $BLENDER)")
    return exe


FLAVOURS = ("binary", "bpy")


def bpy_python():
    return os.environ.get("RADIOSITY_BPY_PYTHON") or sys.executable


def run(blend, script, args, log_path=None, timeout=None, flavour="binary"):
    """Run SCRIPT in Blender (FLAVOUR) on BLEND; returns the dict of its last `RESULT {json}`
    line."""
    user = tempfile.mkdtemp(prefix="radiosity-bench-user-")
    env = dict(os.environ)
    for var, sub in (("BLENDER_USER_CONFIG", "config"), ("BLENDER_USER_SCRIPTS", "scripts"),
                     ("BLENDER_USER_DATAFILES", "datafiles"),
                     ("BLENDER_USER_EXTENSIONS", "extensions")):
        env[var] = os.path.join(user, sub)
    if flavour == "binary":
        env["PATH"] = path_without_pyenv(env.get("PATH", ""))
    env["PYTHONPATH"] = HERE + os.pathsep + env.get("PYTHONPATH", "")
    env["PYTHONDONTWRITEBYTECODE"] = "1"
    if flavour == "binary":
        cmd = [blender_exe(), "-b", "--factory-startup", blend, "--python-exit-code", "1",
               "--python", os.path.join(HERE, script), "--", *map(str, args)]
    elif flavour == "bpy":
        cmd = [bpy_python(), os.path.join(HERE, "run_in_bpy.py"), "--", blend,
               os.path.join(HERE, script), *map(str, args)]
    else:
        raise ValueError(flavour)
    print("$ " + " ".join(cmd), flush=True)
    t = time.perf_counter()
    out_lines = []
    with subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True,
                          env=env, bufsize=1) as proc:
        for line in proc.stdout:
            out_lines.append(line)
            if line.startswith(("[bench", "RESULT", "Error", "Traceback")) or "Error" in line:
                print("   " + line.rstrip(), flush=True)
        proc.wait(timeout=timeout)
    if log_path:
        with open(log_path, "w") as f:
            f.writelines(out_lines)
    shutil.rmtree(user, ignore_errors=True)
    results = [l[len("RESULT "):] for l in out_lines if l.startswith("RESULT ")]
    if proc.returncode != 0 or not results:
        tail = "".join(out_lines[-40:])
        raise SystemExit(f"Blender run failed (exit {proc.returncode}):\n{tail}")
    data = json.loads(results[-1])
    data["_wall"] = time.perf_counter() - t
    return data


def machine():
    """A line about the machine and its load, for the results files."""
    try:
        load = os.getloadavg()
    except OSError:
        load = (float("nan"),) * 3
    return f"{os.cpu_count()} cores, load average {load[0]:.2f}/{load[1]:.2f}/{load[2]:.2f}"


def git_commit():
    """The commit measured, for the results files: HEAD, marked when the solver or the add-on
    (native/, addon/) differ from it in the work tree."""
    def git(*args):
        return subprocess.run(["git", "-C", REPO, *args], capture_output=True, text=True).stdout.strip()
    head = git("rev-parse", "--short", "HEAD") or "unknown"
    code = git("log", "-1", "--format=%h", "--", "native", "addon") or "unknown"
    dirty = " + local changes" if git("status", "--porcelain", "--", "native", "addon") else ""
    # A benchmark branch's HEAD differs from main's by bench scripts only: the solver and add-on
    # commit says which code was measured.
    return f"{head} (solver and add-on as of {code}{dirty})"


def stamp(json_path, **fields):
    """Adds FIELDS (e.g. the commit) to a scene's saved JSON."""
    with open(json_path) as f:
        data = json.load(f)
    data.update(fields)
    with open(json_path, "w") as f:
        json.dump(data, f, indent=1)
