"""(c) Second bake: no duplicated attribute; nothing changed -> the kept solution is used."""


def test_rebake_reuses_and_never_duplicates(run_blender):
    r = run_blender("repeat.py")
    assert all(r["ok"]), r["_log"]
    for name, found in r["names"].items():
        assert found == ["Radiosity"], (name, found)
    for name, types in r["types"].items():
        assert types == [["FLOAT_COLOR", "CORNER"]], (name, types)
    assert set(r["active"].values()) == {"Radiosity"}
    assert r["first"]["cached"] is False
    assert r["second"]["cached"] is True          # cache path taken, not a timing check
    assert r["second"]["mode"] == "full"          # nothing solved: a cached hit reports "full"
    assert r["same_values"]
    assert r["full"]["cached"] is False           # full=True ignores the kept solution
    assert r["preset_change"]["cached"] is False
    assert r["preset_change"]["preset"] == "DRAFT"
    assert r["material_change"]["cached"] is False
    assert r["after_clear"]["cached"] is False
    assert r["readonly"]
    required = {"mode", "seconds", "input_surfaces", "objects", "clusters", "elements", "links",
                "cluster_links", "obj_env_links", "env_env_links", "env_env_links_recomputed",
                "rays"}
    assert required <= set(r["first"])
    assert r["first"]["objects"] == 3 and r["first"]["collections"] == 1
    assert r["first"]["input_surfaces"] == 100 + 1 + 96
