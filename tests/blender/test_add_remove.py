"""Objects added and deleted between bakes go through the kept solver (issue 4), in real
Blender (both flavours), compared with full bakes of the same scenes."""
import pytest

# Goal (issue 4): incremental equals a full bake within 0.5 % NRMSE; bounded here at 2 %, as
# the move test (test_incremental.py) is; the measured figures are printed.
TOL = 0.02


def test_add_move_delete_hide(run_blender):
    r = run_blender("add_remove.py")
    assert all(r["ok"]), r["_log"]
    for key, added, removed in (("add", 1, 0), ("move", 0, 0), ("remove", 0, 1), ("hide", 0, 1)):
        st = r[key]
        assert st["mode"] == "incremental", (key, st.get("full_reason"), r["_log"])
        assert st["cached"] is False
        assert (st["added"], st["removed"]) == (added, removed), (key, st)
        assert r[key + "_full"]["mode"] == "full"
    assert r["move"]["moved"] == 1
    assert r["add"]["objects"] == 4 and r["remove"]["objects"] == 3 and r["hide"]["objects"] == 2
    assert r["cube_lit"] and r["box_gone"]
    if r["first"].get("fake"):
        pytest.skip("numeric checks need the real native module")
    assert r["add"]["objects_added"] == 1 and r["add"]["links_created"] > 0
    assert r["remove"]["objects_removed"] == 1 and r["remove"]["links_removed"] > 0
    print(f"\n[{r['_flavour']}] NRMSE incremental vs full: add {r['add_nrmse']:.4f} move "
          f"{r['move_nrmse']:.4f} delete {r['remove_nrmse']:.4f} hide {r['hide_nrmse']:.4f}; worst "
          f"{r['add_worst']} {r['move_worst']} {r['remove_worst']} {r['hide_worst']}; seconds inc/full "
          + ", ".join(f"{k} {r[k]['seconds']:.2f}/{r[k + '_full']['seconds']:.2f}"
                      for k in ("add", "move", "remove", "hide")))
    for key in ("add", "move", "remove", "hide"):
        assert r[key + "_nrmse"] < TOL, (key, r[key + "_nrmse"])
