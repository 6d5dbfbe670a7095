"""Textured materials and the world, in real Blender, against converged Cycles bakes at HIGH.

References (tests/blender/data/tex_*.npy, 16384 spp, made by
tests/blender/scripts/make_tex_world_references.py with the command in its docstring), per version:
_v3 for 3.4, _v5_0 / _v5_2 for bpy 5.0 / 5.2. The floors' 5.0 and 5.2 bakes are identical; the
sky's models differ between them. Cycles' own noise at 16384 spp: 0.3 % rRMSE (2048 against 16384
spp: 0.8 %).

The error is bench/corner_metric.py's over every corner but the emitter's, covered ones
included. With the final gather on it is, on 3.4 at HIGH: checker 1.98 %, image 1.7 %,
sky 1.8 % (bpy 5.x: sky 1.3 %; before the gather: 1.26, 1.32, 0.20). The tests below judge what the textures and
the world decide: the texture followed corner by corner (median error), the energy and the
colour bled onto the cube (means), NRMSE, and the rRMSE of the uncovered corners.
"""
import os

import pytest

from ui_window import run_ui_window  # noqa: F401  (fixture)

DATA = os.path.join(os.path.dirname(__file__), "data")


def _figures(r):
    e = r["all"]
    return (f"[{r['_flavour']}] rRMSE {e['rrmse']:.4f} (uncovered {e['rrmse_uncovered']:.4f}, "
            f"{e['covered']} covered), NRMSE {e['nrmse']:.4f}, median {e['rel_p50']:.4f}, "
            f"p90 {e['rel_p90']:.4f}, mean ratio {e['mean_ratio']:.4f}; " +
            " ".join(f"{k} ours {[round(x, 4) for x in v['ours_mean']]} ref "
                     f"{[round(x, 4) for x in v['ref_mean']]}" for k, v in r["per_object"].items()))


def _check_common(r):
    assert r["ok"], r["_log"]
    # The scene is left as it was but for our colour attribute.
    assert r["census_same"], r["census_diff"]
    assert all(v == ["Radiosity"] for v in r["attrs_added"].values()), r["attrs_added"]
    assert r["shape_ok"]


def _check_means(r, tol):
    for name, v in r["per_object"].items():
        for a, b in zip(v["ours_mean"], v["ref_mean"]):
            assert abs(a / b - 1.0) <= tol, (name, v)


@pytest.mark.parametrize("kind", ["checker", "image"])
def test_textured_floor_matches_cycles(run_blender, kind):
    # Each Blender against its own Cycles: 3.4's light sampling reads the mesh lamp seen at
    # grazing angles (the cube's sides) too dark (bench/results/reference_bias.md); its floors'
    # references differ from 5.x's by 1.2 % (checker) and 1.0 % (image) rRMSE, cube +0.2 %.
    v = run_blender("blender_version.py")
    ref = os.path.join(DATA, f"tex_{kind}_{v['ref_tag']}.npy")
    assert os.path.exists(ref), f"no Cycles reference of the {kind} floor for Blender {v['blender']}"
    r = run_blender("tex_world_compare.py", "--kind", kind, "--preset", "HIGH", "--ref", ref)
    if r.get("fake"):
        pytest.skip("stand-in native module: no accuracy to check")
    _check_common(r)
    st, e = r["stats"], r["all"]
    print("\n" + _figures(r) + f"; texture evaluation {st['texture_seconds']} s "
          f"({st['texture_pieces']} pieces)")
    assert st["textured_objects"] == 1, st
    # Measured on 3.4 with the final gather on: checker NRMSE 0.0095, median 0.0026,
    # uncovered rRMSE 0.061, all corners 0.090; image 0.0065, 0.0017, 0.035, 0.081. (Before the
    # gather: NRMSE 0.049 / 0.043, rRMSE 1.26 / 1.32.)
    assert e["nrmse"] <= 0.015
    assert e["rel_p50"] <= 0.006
    assert e["rrmse_uncovered"] <= 0.08
    assert abs(e["mean_ratio"] - 1.0) <= 0.02
    _check_means(r, 0.02)
    # Colour bleeding of the floor's mean onto the white cube: its red over green as in Cycles
    # (a grey floor, the old viewport-colour fallback, gives 1.0 against Cycles' 1.08 / 1.13).
    ours, ref = r["per_object"]["Cube"]["ours_mean"], r["per_object"]["Cube"]["ref_mean"]
    assert ref[0] / ref[1] > 1.03
    assert abs((ours[0] / ours[1]) / (ref[0] / ref[1]) - 1.0) <= 0.01, (ours, ref)
    # Every corner within the 2 % goal: at HIGH, checker 0.0181 / 0.0173, image
    # 0.0156 / 0.0144 (3.4 / bpy 5.x, each against its own Cycles); 0.0198 / 0.0170 on 3.4 with
    # an earlier near field. With 16 rays a link or 512 gather rays the checker reads 2.4-2.7 % against either
    # Blender's reference (bench/results/presets_sweep.md): HIGH keeps 32 and 1024. Before
    # the near field took many stratified points and solved both sides of a contact together
    # (the cube's foot corners read 1.5-2.3x Cycles): 0.058 / 0.033; before the transport took
    # the texture inside each polygon (textures.py's pieces: the floor at the cube's foot is
    # white where its polygon's mean is pink): 0.0215 / 0.0182.
    assert e["rrmse"] <= 0.02


def test_sky_world_matches_cycles(run_blender):
    v = run_blender("blender_version.py")
    ref = os.path.join(DATA, f"tex_sky_{v['ref_tag']}.npy")
    if not os.path.exists(ref):
        pytest.skip(f"no Cycles reference of the sky for Blender {v['blender']} ({ref})")
    r = run_blender("tex_world_compare.py", "--kind", "sky", "--preset", "HIGH", "--ref", ref)
    if r.get("fake"):
        pytest.skip("stand-in native module: no accuracy to check")
    _check_common(r)
    st, e = r["stats"], r["all"]
    print("\n" + _figures(r) + f"; world evaluation {st['world_seconds']} s")
    assert st["world_sun"] and st["lights"] == 2, st      # the sun disc as a sun light + the map
    # Measured at HIGH: NRMSE 0.0052 / 0.0035, median 0.0046 / 0.0017, rRMSE 0.0178 / 0.0132
    # (3.4 / bpy 5.x), means within 0.5 %. (With an earlier near field: rRMSE 0.025;
    # before the gather: 0.20.) The acceptance: 2 % rRMSE over every corner.
    assert e["nrmse"] <= 0.015
    assert e["rel_p50"] <= 0.01
    assert e["rrmse"] <= 0.02
    assert abs(e["mean_ratio"] - 1.0) <= 0.02
    _check_means(r, 0.02)


def test_world_directions_follow_blender(run_blender):
    r = run_blender("world_convention.py")
    assert r["ok"], r["_log"]
    if r.get("fake"):
        pytest.skip("stand-in native module")
    print(f"\n[{r['_flavour']}] direction error median {r['direction_err_median']:.2e} p99 "
          f"{r['direction_err_p99']:.2e}; image match {r['env_image_match']:.4f}; "
          f"world map {r['world_seconds']} s; faces {r['faces']}")
    # Each map pixel holds the mean of the direction over it: the centre's, to second order.
    assert r["direction_err_median"] < 2e-3 and r["direction_err_p99"] < 1e-2
    assert r["env_image_match"] > 0.99
    # An HDRI sun of one 0.36-degree texel (67 % of the light): the hot-spot window puts its
    # energy in the map (measured 1.004; without it 1.125 on 3.4, the few map samples' luck).
    print(f"HDRI flux ratio {r['hdri_flux_ratio']:.4f} (unrefined {r['hdri_flux_ratio_unrefined']:.4f}, "
          f"sun share {r['hdri_sun_share']:.2f}, {r['hdri_hot_spots']} hot spot windows)")
    assert r["hdri_hot_spots"] >= 1
    assert abs(r["hdri_flux_ratio"] - 1.0) < 0.02
    assert r["bake_ok"], r["reports"]
    f = r["faces"]
    # Bright toward +X only (radiance 1), rho 0.5, nothing else in the scene.
    assert abs(f["(1, 0, 0)"] - 0.5) < 0.01 and f["(-1, 0, 0)"] < 0.01, f
    for k in ("(0, 1, 0)", "(0, -1, 0)", "(0, 0, 1)", "(0, 0, -1)"):
        assert abs(f[k] - 0.25) < 0.01, f


def test_texture_change_is_incremental(run_blender):
    r = run_blender("tex_incremental.py")
    assert r["ok"], r["_log"]
    if r.get("fake"):
        pytest.skip("stand-in native module")
    print(f"\n[{r['_flavour']}] incremental vs full NRMSE {r['inc_vs_full']:.4f}")
    assert r["mode"] == "incremental"
    assert r["texture_changed"] == 1 and r["reflectance_changed"] == 1
    assert r["changed_floor"] > 0.1
    assert r["inc_vs_full"] < 0.02        # measured 0.009
    assert r["cube_green_over_red"] > 1.03  # the green squares now bleed green
    # Kept evaluations (eval_cache.py): a move bakes no texture and renders no world again.
    assert r["move_textures_baked"] == 0
    assert r["world_cached"] == [False, True]


def test_twin_textured_objects_are_evaluated_once_and_kept(run_blender):
    # The same mesh and textured material in two places: one evaluation for both, so the
    # values a later bake reads from the kept evaluations are those this bake used, and a move
    # of another object is a move, not a texture change (which re-gathers every point).
    r = run_blender("tex_twin_objects.py")
    assert r["ok"], r["_log"]
    if r.get("fake"):
        pytest.skip("stand-in native module")
    assert r["textured"] == 2 and r["baked"] == 1, r
    assert r["mode"] == "incremental", r
    assert r["texture_changed"] == 0 and r["reflectance_changed"] == 0, r
    assert r["twin_lit"] > 0


def test_single_quad_takes_the_texture_mean(run_blender):
    """A checker on a 4-vertex plane: the corners show two squares' colours, the polygon's
    reflectance (the transport's) is the checker's area mean, (red + white) / 2."""
    r = run_blender("tex_single_quad.py")
    assert r["ok"], r["_log"]
    assert r["warnings"] == [], r["warnings"]
    assert r["polygon"] == pytest.approx([0.8, 0.43, 0.425], abs=0.01)
    greens = sorted(round(c[1], 3) for c in r["corners"])
    assert greens == [0.06, 0.06, 0.8, 0.8], r["corners"]
    # An Emission shader whose colour is a red/blue checker, strength 5 (the EMIT bake): corners
    # 5 x red or 5 x blue, the polygon's emission their mean; the plane emits nothing.
    assert r["lamp_polygon"] == pytest.approx([2.5, 0.0, 2.5], abs=0.05)
    assert sorted(tuple(round(x, 3) for x in c) for c in r["lamp_corners"]) == \
        [(0.0, 0.0, 5.0), (0.0, 0.0, 5.0), (5.0, 0.0, 0.0), (5.0, 0.0, 0.0)]
    assert r["plane_emission"] is None or max(map(max, r["plane_emission"])) == 0.0
    # The transport's texture inside the polygons (textures.py's pieces): the plane's pieces
    # hold both squares' reflectance, the lamp's both squares' emission (its elements emit
    # their own part); at most 8 x 8 pieces per polygon.
    assert 4 <= min(r["piece_counts"]) and max(r["piece_counts"]) <= 64, r["piece_counts"]
    assert r["plane_piece_greens"] == [0.06, 0.8], r["plane_piece_greens"]
    assert r["plane_piece_emission"] in (None, 0.0), r["plane_piece_emission"]
    assert r["lamp_piece_emission"] == [[0.0, 0.0, 5.0], [5.0, 0.0, 0.0]], r["lamp_piece_emission"]


def test_bake_button_undo_redo_in_the_ui(run_ui_window):
    """Interactive Blender: Bake (the modal job) on a textured floor under a sky, then undo and
    redo. Cycles' temporary scenes never show; undo takes the colours away, redo restores them."""
    r = run_ui_window("ui_tex_undo.py")
    assert "exception" not in r, r["exception"]
    assert r["bake"]["textured_objects"] == 1 and r["bake"]["world_sun"], r["bake"]
    assert r["bake"]["colours"] == ["Cube", "Floor"], r["bake"]
    assert r["bake"]["census_same"] and r["undo"]["census_same"] and r["redo"]["census_same"], r
    assert r["undo"]["colours"] == [], r["undo"]
    assert r["redo"]["colours"] == ["Cube", "Floor"], r["redo"]
