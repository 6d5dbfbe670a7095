"""The optional sRGB byte copy with exposure (for game export), in real Blender."""


def test_furnace_byte_copy(run_blender):
    r = run_blender("srgb_copy.py")
    for key, exact in (("m2", 188), ("p3", 255), ("m6", 49)):
        c = r[key]
        assert c["ok"], (key, c["err"], r["_log"])
        assert c["exact"] == exact            # the expected bytes of 2 * 2^x (checked by hand)
        assert c["alpha_255"]
        assert c["types"] == [["Radiosity", "FLOAT_COLOR", "CORNER"],
                              ["Radiosity_sRGB", "BYTE_COLOR", "CORNER"]], c["types"]
        assert c["active"] == ["Radiosity"] and c["render"] == ["Radiosity"]
        assert c["stats"]["byte_copy"] == "Radiosity_sRGB"
        if r["fake"]:
            continue        # the stand-in's furnace is exact too, but only per polygon
        assert c["match_floats"], key
        assert c["max_off_exact"] <= 1, (key, c)   # the float bake is within 0.1 % of 2
    # A new exposure re-uses the kept solution: only the bytes change.
    assert r["p3"]["stats"]["cached"] and r["m6"]["stats"]["cached"]
    assert r["off_ok"] and r["off_untouched"]
