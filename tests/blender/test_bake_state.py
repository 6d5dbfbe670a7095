"""Headless, both flavours: which bake the meshes show and the panel's words (the interactive side
is in test_undo.py, test_live.py and test_ui.py)."""


def test_bake_state_and_panel_words(run_blender):
    r = run_blender("bake_state.py")
    assert r["ok"], r["_log"]
    assert r["tokens_one_per_bake"]
    assert r["fresh_after_bake"] is None
    assert r["first"]["headline"].startswith("Bake: solved from scratch")
    assert r["first"]["details"][0].startswith("Why from scratch: no solution was kept")
    assert [c[0] for c in r["first"]["counts"]] == ["Objects", "Polygons", "Elements", "Links",
                                                    "Rays"]
    assert r["stale_after_move"] == "'Box' moved since the bake"
    assert r["stale_after_move_back"] is None
    assert r["second"]["headline"].startswith("Bake: incremental")
    assert r["second"]["details"] == ["Changed: 1 object moved"]
    assert r["stale_after_second"] is None and r["new_token"]
    # Baking again with nothing changed rewrites the kept colours: the panel still names the
    # incremental bake that solved them.
    assert r["cached"] is True
    assert r["third"]["headline"] == r["second"]["headline"]
    assert r["third"]["details"][-1].startswith("Re-written from the kept solution in")
    assert r["settings"]["details"] == ["Why from scratch: the quality or output settings changed"]
    assert r["runs"] == 1 and r["stale_after_live"] is None
    assert r["live"]["headline"].startswith("Live update: incremental")
    assert "incrementally where it can" in r["tip_bake"]
    assert "from scratch" in r["tip_full"] and r["tip_full"] != r["tip_bake"]
    assert r["clear"][0] == "Free Solver Memory" and "\n" not in r["clear"][1]
    assert r["loaded_known"] and r["loaded_stale"] is None and not r["loaded_kept"]
    assert r["loaded_stale_after_move"] == "'Box' moved since the bake"
    assert r["after_load_bake"]["details"][0].startswith("Why from scratch: no solution was kept")
