"""Objects added and deleted between bakes go through the kept solver, in real
Blender (both flavours), compared with full bakes of the same scenes."""
import pytest

# Goal: incremental equals a full bake within 0.5 % NRMSE; bounded here at 2 %, as
# the move test (test_incremental.py) is; the measured figures are printed.
TOL = 0.02


def test_add_move_delete_hide(run_blender):
    r = run_blender("add_remove.py")
    assert all(r["ok"]), r["_log"]
    steps = ("add", "move", "replace", "remove", "hide")
    for key, added, removed, replaced in (("add", 1, 0, 0), ("move", 0, 0, 0), ("replace", 0, 0, 1),
                                          ("remove", 0, 1, 0), ("hide", 0, 1, 0)):
        st = r[key]
        assert st["mode"] == "incremental", (key, st.get("full_reason"), r["_log"])
        assert st["cached"] is False
        assert (st["added"], st["removed"], st["replaced"]) == (added, removed, replaced), (key, st)
        assert r[key + "_full"]["mode"] == "full"
    assert r["move"]["moved"] == 1
    assert r["add"]["objects"] == 4 and r["remove"]["objects"] == 3 and r["hide"]["objects"] == 2
    assert r["cube_lit"] and r["box_gone"]
    if r["first"].get("fake"):
        pytest.skip("numeric checks need the real native module")
    assert r["add"]["objects_added"] == 1 and r["add"]["links_created"] > 0
    assert r["remove"]["objects_removed"] == 1 and r["remove"]["links_removed"] > 0
    print(f"\n[{r['_flavour']}] NRMSE incremental vs full: "
          + ", ".join(f"{k} {r[k + '_nrmse']:.4f} (worst {r[k + '_worst'][0]} {r[k + '_worst'][1]:.4f})"
                      for k in steps)
          + "; seconds inc/full " + ", ".join(f"{k} {r[k]['seconds']:.2f}/{r[k + '_full']['seconds']:.2f}"
                                               for k in steps))
    for key in steps:
        assert r[key + "_nrmse"] < TOL, (key, r[key + "_nrmse"])
