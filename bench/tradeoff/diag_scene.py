"""Where does our error against the cached Cycles reference come from? Inside Blender.

    python3 bench/tradeoff/run_diag.py --scene cornell_box --preset HIGH
    (runs: blender -b SCENE.blend --python bench/tradeoff/diag_scene.py -- --zip Z --ref R
            --preset P [--eps E] --out OUT.json)

Bakes once, then splits the squared error of NRMSE and rRMSE (bench/corner_metric.py, the
trade-off's corners: every corner but emitters', covered ones included, the scene's floor) by
covered / uncovered and by surface group: object x the axis its polygon
faces (e.g. "CornellBox -z" = the ceiling), and by how far the corner is from the nearest
emitter polygon's centre (ceiling halo). Prints shares and each group's errors.
"""
import argparse
import json
import os
import sys

import bpy
import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import bt_common as bt  # noqa: E402


def normals(objs):
    out = []
    for o in objs:
        me = o.data
        n = np.empty(len(me.polygons) * 3)
        me.polygons.foreach_get("normal", n)
        n = n.reshape(-1, 3) @ np.array(o.matrix_world)[:3, :3].T
        tot = np.empty(len(me.polygons), np.int32)
        me.polygons.foreach_get("loop_total", tot)
        out.append(np.repeat(n, tot, axis=0))
    return np.concatenate(out)


def main():
    p = argparse.ArgumentParser()
    p.add_argument("--zip", required=True)
    p.add_argument("--ref", required=True)
    p.add_argument("--preset", default="HIGH")
    p.add_argument("--eps", type=float)
    p.add_argument("--out", required=True)
    a = p.parse_args(bt.args())
    bt.install_addon(a.zip)
    scene = bpy.context.scene
    objs = bt.mesh_objects(scene)
    ref, var, meta = bt.cm.load_reference(a.ref)
    assert meta["objects"] == [o.name for o in objs]
    emit = bt.emitter_mask(objs)
    keep = ~emit
    owner, _ = bt.corner_owner(objs)
    pos = bt.corner_positions(objs)
    nrm = normals(objs)
    st, sec = bt.our_bake(scene, a.preset, a.eps, full=True)
    x = bt.all_corners(objs, bt.ATTR_OURS).astype(np.float64)
    axis = np.argmax(np.abs(nrm), axis=1)
    sign = np.sign(nrm[np.arange(len(nrm)), axis])
    group = np.array([f"{objs[o].name} {'+' if s > 0 else '-'}{'xyz'[ax]}"
                      for o, ax, s in zip(owner, axis, sign)])
    epos = pos[emit]
    diag = float(np.linalg.norm(pos.max(0) - pos.min(0)))
    dist = np.full(len(pos), np.inf)
    if len(epos):
        lo, hi = epos.min(0), epos.max(0)     # the emitters' box (one light in these scenes)
        d = np.maximum(np.maximum(lo - pos, pos - hi), 0)
        dist = np.linalg.norm(d, axis=1) / diag
    floor = bt.cm.scene_floor(ref, emit)
    se = ((x - ref) ** 2).sum(1)
    rel2 = (((x - ref) / np.maximum(ref, floor)) ** 2).sum(1)
    tot_se, tot_rel = se[keep].sum(), rel2[keep].sum()
    rows = []

    def add(name, m):
        m = m & keep
        if not m.any():
            return
        e = bt.errors(x, ref, emit, var, mask=m, floor=floor)
        rows.append({**e, "group": name, "corners": int(m.sum()),
                     "share_nrmse_sq": float(se[m].sum() / tot_se),
                     "share_rrmse_sq": float(rel2[m].sum() / tot_rel)})

    covered = bt.cm.covered_mask(ref)
    add("covered (the reference reads 0)", covered)
    add("uncovered", ~covered)
    for g in sorted(set(group[keep])):
        add(g, group == g)
    for r0, r1 in ((0, 0.02), (0.02, 0.05), (0.05, 0.1), (0.1, 10)):
        add(f"within {r0:g}-{r1:g} diagonals of the light's box", (dist >= r0) & (dist < r1))
    near = dist < 0.02
    res = {"scene": os.path.basename(bpy.data.filepath), "preset": a.preset, "eps": a.eps,
           "seconds": sec, "elements": st["elements"], "all": bt.errors(x, ref, emit, var),
           "without_near_light": bt.errors(x, ref, emit, var, mask=~near, floor=floor),
           "groups": rows}
    with open(a.out, "w") as f:
        json.dump(res, f, indent=1)
    bt.result({"ok": True, "out": a.out})


main()
