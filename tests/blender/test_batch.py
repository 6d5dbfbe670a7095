"""Batch tool: addon/tools/bake_blend.py bakes a saved file and writes --out."""
import json
import os
import zipfile

TOOL = os.path.join(os.path.dirname(__file__), os.pardir, os.pardir, "addon", "tools",
                    "bake_blend.py")


def test_bake_blend_tool(run_blender):
    tmp = run_blender.tmp_path
    src, out = str(tmp / "scene.blend"), str(tmp / "baked.blend")
    run_blender("make_blend.py", "--out", src)
    addon_dir = tmp / "addon_dir"
    with zipfile.ZipFile(run_blender.addon_zip) as z:
        z.extractall(addon_dir)
    r = run_blender(os.path.abspath(TOOL), "--preset", "DRAFT", "--attribute", "GI", "--out", out,
                    "--addon-dir", str(addon_dir), raw=True, blend=src, expect_ok=False)
    assert r["_returncode"] == 0, r["_log"]
    lines = [l for l in r["_stdout"].splitlines() if l.startswith("RADIOSITY_STATS ")]
    assert lines, r["_log"]
    stats = json.loads(lines[-1].split(" ", 1)[1])
    assert stats["mode"] == "full" and stats["preset"] == "DRAFT" and stats["objects"] == 3
    assert os.path.exists(out)
    check = run_blender("inspect_blend.py", "--attribute", "GI", blend=out)
    assert all(v is not None and v > 0 for v in check["maxima"].values()), check["maxima"]


def test_bake_blend_tool_fails_cleanly_on_bad_input(run_blender):
    tmp = run_blender.tmp_path
    src = str(tmp / "scene.blend")
    run_blender("make_blend.py", "--out", src)
    addon_dir = tmp / "addon_dir"
    with zipfile.ZipFile(run_blender.addon_zip) as z:
        z.extractall(addon_dir)
    # an empty attribute name is refused before anything is touched
    r = run_blender(os.path.abspath(TOOL), "--preset", "DRAFT", "--out", str(tmp / "x.blend"),
                    "--addon-dir", str(addon_dir), "--attribute", "",
                    raw=True, blend=src, expect_ok=False)
    assert r["_returncode"] != 0
    assert not os.path.exists(tmp / "x.blend")
