"""The scene the native-only benchmarks' --quick runs use (bench/update_examples.py,
bench/add_remove_examples.py): an example .blend exported by bench/export_scene.py in Debian's
Blender, headless, into a temporary .npz. So a CI smoke run goes through the whole pipeline
(Blender, the add-on's gather, the export, the native module) without any file prepared by hand.
"""
import atexit
import os
import shutil
import subprocess
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "tradeoff"))
import bt_run  # noqa: E402  (Blender on PATH without pyenv, as the Blender tests start it)


def export_example(name="box_room"):
    """Exports example_blends/NAME.blend with its stored move; returns the .npz path."""
    tmp = tempfile.mkdtemp(prefix="radiosity-quick-")
    atexit.register(shutil.rmtree, tmp, True)  # a smoke run leaves nothing behind
    out = os.path.join(tmp, f"{name}.npz")
    env = dict(os.environ, PATH=bt_run.path_without_pyenv(os.environ.get("PATH", "")),
               PYTHONDONTWRITEBYTECODE="1")
    cmd = [bt_run.blender_exe(), "-b", "--factory-startup",
           os.path.join(HERE, "..", "example_blends", f"{name}.blend"), "--python-exit-code", "1",
           "--python", os.path.join(HERE, "export_scene.py"), "--", out]
    proc = subprocess.run(cmd, env=env, capture_output=True, text=True)
    if proc.returncode != 0 or not os.path.exists(out):
        raise SystemExit(f"exporting {name}.blend failed (exit {proc.returncode}):\n"
                         + (proc.stdout + proc.stderr)[-3000:])
    return out
