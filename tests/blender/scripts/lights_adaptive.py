"""Adaptive-mesh output of the point-light scene: T-vertex checks and colours against the
solver's elements; the originals untouched; lighting-only values against radiance / rho."""
import sys

import bpy
import numpy as np

import light_scenes
import rt_common as rt

rt.setup()
objs = light_scenes.build("point")
scene = bpy.context.scene
scene.radiosity.preset = rt.arg("--preset", "MEDIUM")
scene.radiosity.adaptive_mesh = True
loops_before = {o.name: len(o.data.loops) for o in objs}
ok, err, reports = rt.bake()
out = {"ok": ok, "err": err, "fake": rt.native_is_fake(), "stats": rt.last_stats(), "objects": {}}


def tvertex_check(me, mw):
    nv = len(me.vertices)
    co = np.empty(nv * 3)
    me.vertices.foreach_get("co", co)
    co = co.reshape(-1, 3) @ np.asarray(mw)[:3, :3].T + np.asarray(mw)[:3, 3]
    edges = {}
    for p in me.polygons:
        vs = list(p.vertices)
        for i in range(len(vs)):
            e = tuple(sorted((vs[i], vs[(i + 1) % len(vs)])))
            edges[e] = edges.get(e, 0) + 1
    max_share = max(edges.values())
    # A vertex strictly inside another edge (a T-vertex): sweep over x-sorted vertices.
    order = np.argsort(co[:, 0])
    xs = co[order, 0]
    diag = np.linalg.norm(co.max(0) - co.min(0))
    tol = 1e-7 * diag
    t_vertices = 0
    for a, b in edges:
        pa, pb = co[a], co[b]
        lo, hi = min(pa[0], pb[0]) - tol, max(pa[0], pb[0]) + tol
        cand = order[np.searchsorted(xs, lo):np.searchsorted(xs, hi, side="right")]
        cand = cand[(cand != a) & (cand != b)]
        if not len(cand):
            continue
        d = pb - pa
        L2 = d @ d
        t = (co[cand] - pa) @ d / L2
        dist = np.linalg.norm(co[cand] - (pa + np.outer(t, d)), axis=1)
        t_vertices += int(((t > 1e-9) & (t < 1 - 1e-9) & (dist < tol)).sum())
    return max_share, t_vertices, co


if ok:
    import radiosity.core.session as cs
    entry = next(x.kept for x in cs.sessions().values() if x.kept is not None)
    solver = entry.solver
    for o in objs:
        ad = bpy.data.objects.get(o.name + ".radiosity")
        info = {"exists": ad is not None, "original_loops_same": len(o.data.loops) == loops_before[o.name]}
        if ad is not None:
            me = ad.data
            mw = np.array(ad.matrix_world)
            max_share, tv, co = tvertex_check(me, mw)
            col = rt.corner_colors(ad)[:, :3]
            src = np.empty(len(me.polygons), np.int32)
            me.attributes["radiosity_source_face"].data.foreach_get("value", src)
            oid = entry.object_ids[o.name]
            worst = 0.0
            area = 0.0
            for p in me.polygons:
                vs = list(p.vertices)
                c = co[vs].mean(axis=0)
                val = np.array(solver.radiance_at(oid, int(src[p.index]), tuple(c)))
                mine = col[p.loop_start]
                worst = max(worst, float(np.abs(val - mine).max() / max(1e-6, np.abs(val).max())))
                area += p.area
            info.update(faces=len(me.polygons), input_faces=len(o.data.polygons), max_edge_share=max_share,
                        t_vertices=tv, colour_worst_rel=worst, area=area,
                        input_area=sum(p.area for p in o.data.polygons))
        out["objects"][o.name] = info
rt.result(**out)
