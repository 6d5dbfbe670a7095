"""Corner-exact tests: every corner holds the radiance at its vertex, seen with its face's
normal, as Cycles bakes it (CONTRACT.md "Output"), not the average of the element around it.

Each test bakes a scene of corner_scenes.py with the add-on in real Blender (both conftest
flavours: Debian's Blender 3.4 and PyPI's bpy 5.0) and compares every corner with a converged
Cycles bake cached in tests/blender/data (tests/blender/scripts/make_corner_references.py: 16,384
spp as two independent 8,192-spp halves with seeds 1 and 2; stored as [mean, |a-b|/2], the second
being the reference's per-corner noise; one reference per Blender generation, v3 = 3.x, v4 = 4.0+,
as the area/spot light units and the Principled BSDF differ), or, for the lamp, with the closed
form.

Metric (NOTES.md): rRMSE = sqrt(mean(((x - r) / max(r, 0.05 mean r))^2)) over every corner and
channel of the set named, emitters' corners left out, covered corners (r = 0) kept. Where a
target is 2 %, the reference's own noise n (the same rRMSE of |a-b|/2) is removed in quadrature,
sqrt(max(e^2 - n^2, 0)); every test also checks that n is well under its target, so the
correction can never hide an error. Every test prints its measured figure (pytest -s).
"""
import json
import math
import os

import numpy as np
import pytest

HERE = os.path.dirname(os.path.abspath(__file__))
RUNNER = os.path.join(HERE, "corner_scenes.py")     # absolute: run_blender takes it as given
DATA = os.path.join(HERE, "data")

CONTACT_TOL = 0.10           # per corner, on the contact line
UNDER_BOX_TOL = 1e-3         # of the floor's mean reference radiance
LAMP_TOL = 0.02              # per corner and channel, against the analytic value
LEG_TOL = 0.05               # rRMSE over the leg's corners
FACTORY_TOL = 0.02           # rRMSE over the cube's corners, reference noise removed
ROOM_TOL = {"DRAFT": 0.10, "MEDIUM": 0.05, "HIGH": 0.02}


# --- helpers -----------------------------------------------------------------------------------

def bake(run_blender, case, preset="HIGH"):
    """Bake `case` with the add-on; (RESULT dict, per-corner arrays of corner_scenes._run)."""
    out = run_blender.tmp_path / f"{case}_{preset}.npz"
    r = run_blender(RUNNER, "--case", case, "--preset", preset, "--out", str(out))
    assert r["ok"], r["_log"]
    if r["fake"]:
        pytest.skip("stand-in native module: no accuracy to check")
    with np.load(out) as z:
        d = {k: z[k] for k in z.files}
    return r, d


def reference(case, tag, n_corners, suffix=""):
    """(ref, noise, meta) of corner_<case><suffix>_<tag>; references exist for v3 and v4."""
    stem = os.path.join(DATA, f"corner_{case}{suffix}_{tag}")
    assert os.path.exists(stem + ".npy"), f"missing reference {stem}.npy: run make_corner_references.py"
    stack = np.load(stem + ".npy").astype(np.float64)
    with open(os.path.join(DATA, f"corner_{case}_{tag}.json")) as f:
        meta = json.load(f)
    assert stack.shape == (2, n_corners, 3), (stack.shape, n_corners)
    return stack[0], stack[1], meta


def rrmse(x, r, noise, keep):
    """(measured rRMSE, the reference noise's rRMSE, measured with the noise removed in
    quadrature) over the corners `keep`, all channels."""
    d = np.maximum(r[keep], 0.05 * r[keep].mean())
    e = float(np.sqrt(np.mean(((x[keep] - r[keep]) / d) ** 2)))
    n = float(np.sqrt(np.mean((noise[keep] / d) ** 2)))
    return e, n, math.sqrt(max(e * e - n * n, 0.0))


def label(r):
    return f"[{r['_flavour']} {r['blender']} {r['preset']}]"


def point_polygon_form_factor(p, normal, poly):
    """Form factor from points p (P,3) with unit normal (3,) to a uniform Lambertian polygon
    (m,3) wholly in front of them, by Lambert's contour formula:
    F = 1/(2 pi) |sum_i angle(r_i, r_i+1) n . (r_i x r_i+1) / |r_i x r_i+1||, r_i = v_i - p."""
    r0 = poly[None, :, :] - p[:, None, :]
    r1 = np.roll(r0, -1, axis=1)
    c = np.cross(r0, r1)
    cn = np.linalg.norm(c, axis=2)
    ang = np.arctan2(cn, np.einsum("pik,pik->pi", r0, r1))
    return np.abs(np.sum(ang * (c @ normal) / cn, axis=1)) / (2 * math.pi)


def inside_polygon_xy(p, poly):
    """Points p (P,2) strictly inside the convex polygon (m,2) (either winding)."""
    e = np.roll(poly, -1, axis=0) - poly
    s = e[None, :, 0] * (p[:, None, 1] - poly[None, :, 1]) - e[None, :, 1] * (p[:, None, 0] - poly[None, :, 0])
    return np.all(s > 1e-9, axis=1) | np.all(s < -1e-9, axis=1)


# --- 1. a box standing on a gridded floor ------------------------------------------------------

def test_contact_under_box_and_on_contact_line(run_blender):
    """Floor corners under the box read 0 (< 1e-3 of the floor's mean reference); floor corners
    on the footprint's edge match Cycles, each corner and channel within
    |x - r| <= 0.10 max(r, 0.05 mean(r over the floor)). HIGH.

    On the edge, the four corners of one vertex differ in Cycles: it evaluates a corner not at
    the vertex itself but nudged towards the centroid of the corner's first triangle by
    1e-4 max(max|P|, 1) (corner_scenes.cycles_sample_points). So the corners of the quads under
    the box read 0 and those of the quads outside read the half-open hemisphere's light, lit or
    in the box's shadow depending on the side the nudge takes them to. Both kinds are checked."""
    r, d = bake(run_blender, "contact")
    x, pos = d["ours"], d["pos"]
    ref, noise, meta = reference("contact", r["tag"], len(x))
    floor = d["object"] == 0
    lo, hi = np.array(r["info"]["footprint_lo"]), np.array(r["info"]["footprint_hi"])

    def inside(xy, closed):
        m = 1e-6 if closed else -1e-6
        return np.all((xy >= lo - m) & (xy <= hi + m), axis=1)

    under = floor & inside(pos[:, :2], False)
    line = floor & inside(pos[:, :2], True) & ~under
    inner = line & inside(d["sample"][:, :2], False)     # Cycles samples them under the box
    outer = line & ~inner
    assert (under.sum(), line.sum(), inner.sum()) == (9 * 4, 16 * 4, 12 * 2 + 4), \
        (under.sum(), line.sum(), inner.sum())

    mean_floor = ref[floor].mean()
    scale = np.maximum(ref, 0.05 * mean_floor)
    rel = np.abs(x - ref) / scale
    under_worst = float(np.abs(x[under]).max() / mean_floor)
    line_worst = float(rel[line].max())
    e, n, _ = rrmse(x, ref, noise, ~d["emitter"])
    print(f"\n{label(r)} contact: under the box max |x| / mean(floor ref) {under_worst:.2e} "
          f"(target < {UNDER_BOX_TOL:g}); contact line worst |x-r|/max(r, 0.05 mean) "
          f"{line_worst:.3f} (target <= {CONTACT_TOL}): {int((rel[line] > CONTACT_TOL).any(axis=1).sum())}"
          f"/{int(line.sum())} corners over; quads outside worst {rel[outer].max():.3f}, ours/ref "
          f"{x[outer].mean() / ref[outer].mean():.3f}; quads under the box (ref 0) worst "
          f"{rel[inner].max():.3f}; scene rRMSE {e:.4f} (ref noise {n:.4f}); ref noise on the "
          f"line worst {(noise[line] / scale[line]).max():.4f}")
    # The reference agrees: nothing reaches under the box, and its noise on the line is small.
    assert ref[under].max() < UNDER_BOX_TOL * mean_floor
    assert ref[inner].max() < UNDER_BOX_TOL * mean_floor
    assert (noise[line] / scale[line]).max() < CONTACT_TOL / 3, (noise[line] / scale[line]).max()
    assert under_worst < UNDER_BOX_TOL
    # Corners beside the box that Cycles reads lit match it (their values come from the lamp).
    lit = outer & (ref.max(axis=1) > 0.05 * mean_floor)
    assert rel[lit].max() <= CONTACT_TOL, rel[lit].max()
    # The box's corner vertex (-0.3, 0.3) is the hard one: 0.05 mm from the -x face and 0.1 mm
    # from its end, in the box's shadow, with the lamp's penumbra on the floor in front of the
    # same face a tenth of a millimetre away. The near field (near_field.cpp)
    # reads the face's first millimetre, which sees that penumbra: read as the point's own
    # (dark) floor it left the vertex 25-30 % dark (a strict xfail until the near field took
    # the floor's direct light at the spots the face sees, direct_variation). Natively, HIGH,
    # seeds 1-8: 0.00282-0.00314 against 0.0031 / 0.0033 (3.4 / 5.x references).
    assert line_worst <= CONTACT_TOL


# --- 2. a lamp 1 mm under a gridded ceiling ----------------------------------------------------

def test_lamp_under_ceiling_matches_analytic(run_blender):
    """Ceiling corners above the lamp (vertex inside the lamp's outline seen from above) equal
    rho x L x F(point, lamp) within 2 % per corner and channel (Lambert's contour formula; the
    rest of the scene is a black world, so nothing else reaches the ceiling). HIGH.

    The point is where Cycles evaluates the corner: the vertex nudged 0.1-0.15 mm into the
    corner's first triangle (corner_scenes.cycles_sample_points). It matters at a vertex 5 mm
    from the lamp's rim (F = 0.967): there the four corners' nudged points differ by up to 0.5 %
    in F; the closed form at the nudged points matches the Cycles reference within 0.05 %."""
    r, d = bake(run_blender, "lamp")
    info = r["info"]
    x, pos, nrm, smp = d["ours"], d["pos"], d["normal"], d["sample"]
    ceiling = d["object"] == 0
    poly = np.array(info["lamp_polygon"])
    assert np.allclose(nrm[ceiling], [0, 0, -1], atol=1e-6)
    analytic = np.zeros_like(x)
    k = np.array(info["rho"]) * np.array(info["radiance"])
    F = point_polygon_form_factor(smp[ceiling], np.array([0.0, 0.0, -1.0]), poly)
    analytic[ceiling] = F[:, None] * k
    at_vertex = np.zeros_like(x)
    at_vertex[ceiling] = point_polygon_form_factor(pos[ceiling], np.array([0.0, 0.0, -1.0]), poly)[:, None] * k
    above = ceiling & inside_polygon_xy(pos[:, :2], poly[:, :2])
    assert len(np.unique(d["vertex"][above])) >= 4, "the lamp covers too few ceiling vertices"

    # The closed form against the Cycles bake of the same scene (a check of this test itself).
    ref, noise, meta = reference("lamp", r["tag"], len(x))
    cyc_rel = np.abs(ref[above] - analytic[above]) / analytic[above]

    rel = np.abs(x[above] - analytic[above]) / analytic[above]
    worst = float(rel.max())
    near = ceiling & ~above
    e_all, _, _ = rrmse(x, analytic, np.zeros_like(x), ceiling)
    print(f"\n{label(r)} lamp: {int(above.sum())} corners above the lamp (F {F[above[ceiling]].min():.4f}"
          f"-{F[above[ceiling]].max():.4f}), worst |x-a|/a {worst:.4f} (target <= {LAMP_TOL}), mean "
          f"ours/analytic {x[above].mean() / analytic[above].mean():.4f}; Cycles vs analytic worst "
          f"{cyc_rel.max():.5f} (at the vertices instead: "
          f"{(np.abs(ref[above] - at_vertex[above]) / at_vertex[above]).max():.4f}); whole ceiling "
          f"rRMSE vs analytic {e_all:.4f}, vs Cycles {rrmse(x, ref, noise, ceiling)[0]:.4f}; "
          f"outside the lamp worst abs err "
          f"{np.abs(x[near] - analytic[near]).max():.4f}")
    assert cyc_rel.max() < 0.002, cyc_rel.max()
    assert worst <= LAMP_TOL


# --- 3. a thin leg on a floor ------------------------------------------------------------------

def test_thin_leg_matches_cycles(run_blender):
    """A 4 x 4 x 70 cm leg on a floor, lit by a point light: rRMSE over the leg's 232 corners
    (all channels, its bottom face's included) <= 5 % against Cycles. HIGH.

    The bottom row matters most: Cycles evaluates those corners 50-90 um above the floor (the
    nudge of corner_scenes.cycles_sample_points), where the lower half of the hemisphere sees
    only the floor right at the leg's foot. On the shadowed sides that floor is in the leg's
    own shadow near the (-x, +y) edge, so two corners there read ~0 while their neighbours on
    the same side read half the row above; the bottom face (facing the floor) reads 0."""
    r, d = bake(run_blender, "leg")
    x = d["ours"]
    ref, noise, meta = reference("leg", r["tag"], len(x))
    leg = d["object"] == 1
    e, n, _ = rrmse(x, ref, noise, leg)
    z = d["pos"][:, 2]
    scale = np.maximum(ref[leg], 0.05 * ref[leg].mean())
    rel = np.abs(x[leg] - ref[leg]) / scale
    k = int(np.argmax(rel.max(axis=1)))
    sides = {}
    for name, axis, sign in (("-x", 0, -1), ("+x", 0, 1), ("-y", 1, -1), ("+y", 1, 1), ("top", 2, 1)):
        m = leg & (np.abs(d["normal"][:, axis] - sign) < 1e-6)
        sides[name] = round(float(x[m].mean() / ref[m].mean()), 3)
    above_foot = leg & (z > 1e-6)
    print(f"\n{label(r)} leg: rRMSE over {int(leg.sum())} leg corners {e:.4f} (target <= {LEG_TOL}; "
          f"ref noise {n:.4f}); worst corner {rel.max():.3f} at z={z[leg][k]:.3f}; without the "
          f"corners at z=0: {rrmse(x, ref, noise, above_foot)[0]:.4f}; ours/ref by side {sides}")
    assert n < LEG_TOL / 3, n
    assert e <= LEG_TOL


# --- 4. Blender's factory-startup scene --------------------------------------------------------

def test_factory_startup_matches_cycles(run_blender):
    """The default cube, its 1000 W point light and the grey world, at HIGH: rRMSE over the 24
    corners <= 2 % (reference noise removed in quadrature). The reference is Cycles' COMBINED
    bake of the diffuse part (glossy pass off): the contract's "Principled BSDF (diffuse part)".
    The full COMBINED bake with the specular layer is stored too and its figure printed.

    In bpy 5.x (Principled v2) Cycles' diffuse part of this material is 0.963 of Base Color x
    irradiance / pi (its dielectric layer keeps the rest; measured on the faces only the world
    lights: 0.0392 against 0.8 x 0.0509 = 0.0407); the add-on measures that share with a
    one-quad Cycles bake (addon/radiosity/principled.py). Before it did, that flavour scored
    3.9 %."""
    r, d = bake(run_blender, "factory")
    x = d["ours"]
    ref, noise, meta = reference("factory", r["tag"], len(x))
    keep = np.ones(len(x), bool)
    e, n, e_clean = rrmse(x, ref, noise, keep)
    full, full_noise, _ = reference("factory", r["tag"], len(x), "_combined")
    e_full = rrmse(x, full, full_noise, keep)[0]
    print(f"\n{label(r)} factory: rRMSE {e:.4f}, ref noise {n:.4f}, noise removed {e_clean:.4f} "
          f"(target <= {FACTORY_TOL}); ours/ref mean {x.mean() / ref.mean():.4f}; against the "
          f"COMBINED bake with glossy {e_full:.4f} (ours/ref {x.mean() / full.mean():.4f})")
    assert n < FACTORY_TOL / 3, n
    assert e_clean <= FACTORY_TOL


# --- 5. a room with point, spot, area and sun lights -------------------------------------------

@pytest.mark.parametrize("preset", ("DRAFT", "MEDIUM", "HIGH"))
def test_lights_room_presets(run_blender, preset):
    """Open room (floor and two walls, no ceiling: the sun gets in) with a cube, lit by a point,
    a spot, an area and a sun light: rRMSE over every corner <= 10 % / 5 % / 2 % at DRAFT /
    MEDIUM / HIGH (reference noise removed in quadrature)."""
    r, d = bake(run_blender, "room", preset)
    x = d["ours"]
    ref, noise, meta = reference("room", r["tag"], len(x))
    keep = ~d["emitter"]
    e, n, e_clean = rrmse(x, ref, noise, keep)
    tol = ROOM_TOL[preset]
    per = {}
    for k, name in enumerate(meta["objects"]):
        m = d["object"] == k
        per[name] = round(rrmse(x, ref, noise, m)[0], 4)
    st = r["stats"] or {}
    print(f"\n{label(r)} room: rRMSE {e:.4f}, ref noise {n:.4f}, noise removed {e_clean:.4f} "
          f"(target <= {tol}); ours/ref mean {x[keep].mean() / ref[keep].mean():.4f}; per object "
          f"{per}; {st.get('seconds', float('nan')):.1f} s, {st.get('elements')} elements")
    assert n < tol / 3, n
    assert e_clean <= tol
