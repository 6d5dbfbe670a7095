"""The example files open looking through their camera (the factory viewport faced a
bare wall inside the rooms). The window itself is checked under Xvfb in test_ui_panel.py."""
import glob
import os

HERE = os.path.dirname(os.path.abspath(__file__))
EXAMPLES = sorted(glob.glob(os.path.join(HERE, "..", "..", "example_blends", "*.blend")))


def test_examples_open_through_their_camera(run_blender):
    assert EXAMPLES
    r = run_blender("example_view.py", *map(os.path.abspath, EXAMPLES))
    assert sorted(r["files"]) == sorted(map(os.path.basename, EXAMPLES)), r["_log"]
    for name, f in r["files"].items():
        assert f["camera"], name
        assert f["views"] and all(v == "CAMERA" for v in f["views"]), (name, f["views"])
