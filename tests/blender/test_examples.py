"""Every example_blends/*.blend bakes through the batch tool without warnings."""
import glob
import json
import os

import pytest

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.dirname(os.path.dirname(HERE))
TOOL = os.path.join(REPO, "addon", "tools", "bake_blend.py")
EXAMPLES = sorted(glob.glob(os.path.join(REPO, "example_blends", "*.blend")))


@pytest.mark.parametrize("blend", EXAMPLES or [None],
                         ids=[os.path.basename(b) for b in EXAMPLES] or ["none"])
def test_example_bakes(run_blender, blend):
    if blend is None:
        pytest.skip("no example_blends/*.blend")
    import zipfile
    tmp = run_blender.tmp_path
    addon_dir = tmp / "addon_dir"
    with zipfile.ZipFile(run_blender.addon_zip) as z:
        z.extractall(addon_dir)
    out = str(tmp / "baked.blend")
    r = run_blender(TOOL, "--preset", "DRAFT", "--out", out, "--addon-dir", str(addon_dir),
                    raw=True, blend=blend, expect_ok=False)
    assert r["_returncode"] == 0, r["_log"]
    assert "Warning: " not in r["_stdout"], r["_log"]
    stats = json.loads([l for l in r["_stdout"].splitlines()
                        if l.startswith("RADIOSITY_STATS ")][-1].split(" ", 1)[1])
    assert stats["written_objects"] >= 1 and stats["elements"] > 0
    check = run_blender("inspect_blend.py", blend=out)
    assert all(v is not None and v > 0 for v in check["maxima"].values()), check["maxima"]
