"""Gathering rules: visibility, collections as clusters, shared/modified meshes, materials."""


def test_gather_rules(run_blender):
    r = run_blender("gather_rules.py")
    assert r["ok"], r["_log"]
    w = r["written"]
    # Subdivided: a modifier changes its corner layout; its corners take the evaluated
    # corners' values.
    for name in ("Floor", "Light", "Box", "Displaced", "Tex1", "Tex2", "TwoColls", "Nested",
                 "Subdivided"):
        assert w[name], name
    for name in ("Hidden", "NoRender", "InExcluded", "InRenderOff"):
        assert not w[name], name
    warnings = [m for level, m in r["reports"] if level == "WARNING"]
    # A textured material is evaluated by Cycles (textures.py): no fallback warning,
    # both objects that use it are evaluated.
    assert not any("Checker" in m for m in warnings), warnings
    assert r["stats"].get("textured_objects") == 2, r["stats"]
    assert any("FloorDup" in m and "Floor" in m for m in warnings), warnings
    assert not any("Subdivided" in m for m in warnings), warnings
    st = r["stats"]
    # Floor Light Box FloorDup Subdivided Displaced Tex1 Tex2 Label TwoColls Nested
    assert st["objects"] == 11, st
    assert st["collections"] == 3, st        # Props, First, First/Inner (not Second)
    assert st["written_objects"] == 9, st
    assert st["scene_objects"] == 11 and st["instances"] == 0, st
    assert abs(r["mirror_mean_ratio"] - 1.0) < 0.02, r["mirror_mean_ratio"]
