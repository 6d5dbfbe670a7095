"""Energy balance of a native full solve of a closed scene, and its reflectors' absorbed power
against the cached Cycles reference (bench/results/brightness.md explains what it found).

In a closed scene every watt emitted is absorbed somewhere, so

    emitted  = 2 pi sum_emitter E A                      (mesh emitters emit on both sides)
    absorbed = pi sum_leaf (1 - rho) * (irradiance/pi) * A  over both sides that light reaches

must agree; a solver that creates (or loses) light shows it here whatever its links look like.
The leaves' irradiance / pi comes from Solver.leaf_mesh(i, lighting_only=True) (front sides).
Reflectors' back sides face outside in the example rooms and get no light; an emitter's back
side (the lamp's top, in the 1-unit gap under the ceiling) does, so with --back the scene is
solved a second time with the emitters' polygons reversed to read that side. That figure is
only as good as the emitter's leaves: a black emitter is never refined (the oracle weighs
errors by the receiver's reflectance), and the chair room's 4x4 lamp leaves average its top
to irradiance/pi 7.96 where the ceiling above it is at 9.58 (box room: 5x5 leaves, 9.3).

The second figure needs no back side: the power the reflectors absorb, from per-corner values
(each input polygon's corners averaged, times pi (1 - rho) / rho * area), ours and Cycles'
(bench/tradeoff/refs/SCENE_cycles.npz, corners of objects sorted by name). Where the emitters
absorb the same in both (their surroundings match), the ratio is the energy one solver has
more than the other.

    python3 bench/energy_balance.py [--native-dir DIR] [--preset MEDIUM] [--closure-rays N] [--back] SCENE.npz

SCENE.npz as exported by bench/export_scene.py (e.g. /tmp/box_room.npz).
"""
import argparse
import os
import sys

import numpy as np

ROOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..")


def polygon_area(p):
    n = np.zeros(3)
    for k in range(len(p)):
        n += np.cross(p[k], p[(k + 1) % len(p)])
    return 0.5 * float(np.linalg.norm(n))


def solve(rn, ue, z, preset, closure_rays):
    st = rn.Settings.preset(preset)
    if closure_rays is not None:
        st.closure_rays = closure_rays
    s = rn.Solver(ue.build_scene(z), st)
    s.solve()
    return s


def leaf_absorbed(s, i, rho):
    """pi * sum (1 - rho) * irradiance/pi * area over object i's front-side leaves."""
    lm = s.leaf_mesh(i, True)
    v, lt, cv = lm["vertices"], lm["loop_totals"], lm["corner_verts"]
    starts = np.concatenate([[0], np.cumsum(lt)[:-1]]).astype(int)
    area = np.array([polygon_area(v[cv[a:a + b]]) for a, b in zip(starts, lt)])
    return np.pi * np.sum((1.0 - rho[lm["source_face"]]) * lm["values"] * area[:, None], axis=0)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--native-dir", default=os.path.join(ROOT, "build", "native"))
    ap.add_argument("--preset", default="MEDIUM")
    ap.add_argument("--closure-rays", type=int, default=None, help="0 switches the closure correction off")
    ap.add_argument("--back", action="store_true", help="solve again, emitters reversed, for their back sides")
    ap.add_argument("scene")
    a = ap.parse_args()
    os.environ["RADIOSITY_NATIVE_DIR"] = a.native_dir
    sys.path.insert(0, os.path.join(ROOT, "bench"))
    import update_examples as ue  # imports the module from RADIOSITY_NATIVE_DIR
    rn = ue.rn

    name = os.path.splitext(os.path.basename(a.scene))[0]
    z = dict(np.load(a.scene))
    n = len(z["objects"])
    names = [str(o).split("\t")[0] for o in z["objects"]]
    emitters = [i for i in range(n) if np.any(z[f"o{i}_emission"] > 0)]
    s = solve(rn, ue, z, a.preset, a.closure_rays)

    emitted = np.zeros(3)
    refl = np.zeros(3)
    emit_front = np.zeros(3)
    for i in range(n):
        rho, em = z[f"o{i}_reflectance"], z[f"o{i}_emission"]
        v, cv, ls, lt = z[f"o{i}_vertices"], z[f"o{i}_corner_verts"], z[f"o{i}_loop_starts"], z[f"o{i}_loop_totals"]
        area = np.array([polygon_area(v[cv[s0:s0 + k]]) for s0, k in zip(ls, lt)])
        emitted += 2.0 * np.pi * np.sum(em * area[:, None], axis=0)
        if i in emitters:
            emit_front += leaf_absorbed(s, i, rho)
        else:
            refl += leaf_absorbed(s, i, rho)
    emit_back = np.zeros(3)
    if a.back and emitters:
        z2 = dict(z)
        for i in emitters:
            cv = z[f"o{i}_corner_verts"].copy()
            for s0, k in zip(z[f"o{i}_loop_starts"], z[f"o{i}_loop_totals"]):
                cv[s0:s0 + k] = cv[s0:s0 + k][::-1]
            z2[f"o{i}_corner_verts"] = cv
        s2 = solve(rn, ue, z2, a.preset, a.closure_rays)
        for i in emitters:
            emit_back += leaf_absorbed(s2, i, z[f"o{i}_reflectance"])
    fmt = lambda x: "(" + ", ".join(f"{c:.0f}" for c in x) + ")"
    print(f"{name} {a.preset} closure_rays={a.closure_rays if a.closure_rays is not None else 'preset'}")
    print(f"  emitted {fmt(emitted)}; absorbed: reflectors {fmt(refl)}, emitters front {fmt(emit_front)}"
          + (f", emitters back {fmt(emit_back)}" if a.back else ""))
    if a.back:
        print(f"  absorbed / emitted {np.round((refl + emit_front + emit_back) / emitted, 4)}")

    ref_path = os.path.join(ROOT, "bench", "tradeoff", "refs", f"{name}_cycles.npz")
    if not os.path.exists(ref_path):
        return
    ref = np.load(ref_path, allow_pickle=True)["corners"]
    off = 0
    ours_c, cyc_c = np.zeros(3), np.zeros(3)
    for i in sorted(range(n), key=lambda j: names[j]):
        x = s.corner_radiance(i)
        r = ref[off:off + len(x)]
        off += len(x)
        if i in emitters:
            continue
        rho = z[f"o{i}_reflectance"]
        v, cv = z[f"o{i}_vertices"], z[f"o{i}_corner_verts"]
        for f, (s0, k) in enumerate(zip(z[f"o{i}_loop_starts"], z[f"o{i}_loop_totals"])):
            if np.any(rho[f] <= 0):
                continue
            w = np.pi * (1.0 - rho[f]) / rho[f] * polygon_area(v[cv[s0:s0 + k]])
            ours_c += w * x[s0:s0 + k].mean(axis=0)
            cyc_c += w * r[s0:s0 + k].mean(axis=0)
    print(f"  reflectors' absorbed power from corners: ours {fmt(ours_c)}, Cycles {fmt(cyc_c)}, "
          f"ours/Cycles {np.round(ours_c / cyc_c, 4)}, Cycles / emitted {np.round(cyc_c / emitted, 4)}")


if __name__ == "__main__":
    main()
