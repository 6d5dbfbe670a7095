"""Meshes from Bevel and Subdivision Surface (warped quads) baked, moved and turned into a wall,
re-baked, in real Blender (every flavour): finite, non-negative output, and the incremental
update equal to a full bake of the moved scene."""


def test_bevelled_armchair_moved_and_turned_into_a_wall(run_blender):
    r = run_blender("warped_armchair.py")
    assert all(r["ok"]), r["_log"]
    assert r["first_sane"] and r["move_sane"] and r["full_sane"], r
    assert r["first"]["mode"] == "full" and r["move"]["mode"] == "incremental", r
    assert r["move"]["moved"] == 4, r["move"]
    print(f"\n[{r['_flavour']}] {r['corners']} corners, {r['first']['input_surfaces']} polygons; "
          f"NRMSE incremental vs full {r['nrmse']:.4f}; seconds first {r['first']['seconds']:.2f} "
          f"update {r['move']['seconds']:.2f} full {r['move_full']['seconds']:.2f}")
    assert r["nrmse"] < 0.01, r["nrmse"]
