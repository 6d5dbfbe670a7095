"""(a) Furnace: a closed box with rho=0.5, E=1 everywhere is B = 2 at every corner (0.1 %)."""


def test_furnace_is_two_everywhere(run_blender):
    r = run_blender("furnace.py", "--preset", "MEDIUM", "--n", "4")
    assert r["ok"], r["_log"]
    assert r["alpha_ok"]
    assert r["corners"] == 6 * 16 * 4
    assert r["max_rel_err"] <= 1e-3, r
    st = r["stats"]
    assert st["mode"] == "full" and st["objects"] == 6 and st["collections"] == 2
    assert st["clusters"] >= 2
