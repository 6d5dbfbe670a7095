#!/usr/bin/env python3
"""Whether two builds of the solver give the same corners: for a change meant to keep behaviour
(a refactor), run this with the build before and the build after.

    python3 scripts/same_output.py --a /path/to/build-before/native --b build/native \
        [--presets MEDIUM[,HIGH...]] [--seeds 1[,2...]] [--until STAGE] [SCENE ...]

Per scene (example scenes by name -- cornell_box, box_room, chair_room, full_room, lights_room,
exported from their .blend in Debian's Blender -- or exported .npz files), preset and seed, each
build's module runs in its own process one solver through these stages, each an edit of the
kept solution and each compared:

    solve     a full solve with the seed
    preview   the move previewed (the live drag's preview): the scene's stored move, or, for a
              scene that stores none (lights_room), one made here: its smallest non-emitting
              object (by area) translated along x by 10 % of the scene's x extent (toward the side with
              room for it)
    update    the move applied (move_object) and solved as an update
    material  the largest non-emitting object other than the moved one: reflectance x 0.8, update
    remove    the moved object (the first, if the move has several) removed, update
    add       the same object added back where it stood before the move (a new id), update
    light     every light's intensity x 0.5 (set_light), update -- scenes with lights
    emission  every emitting mesh's emission x 0.5 (set_emission), update -- scenes with one

--until update runs the first three only (the check before the edit stages: about 3 minutes for
the five scenes at MEDIUM on two shared cores, against 5 to 8 for all stages). A stage the module lacks (an older build) is
skipped and said so; "add" runs only with "remove". Every corner value of every object
(preview: the corners it changes) is compared bit for bit; the script prints per scene,
preset, seed and stage how many values differ and the largest difference, with the update's
mode (incremental or full) and how many corner values the edit changed as build A ran it, and
exits 1 when any differs.
"""
import argparse
import dataclasses
import json
import os
import subprocess
import sys
import tempfile
import time

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.join(HERE, "..")
SCENES = ("cornell_box", "box_room", "chair_room", "full_room", "lights_room")
STAGES = ("solve", "preview", "update", "material", "remove", "add", "light", "emission")
MADE_MOVE_SHARE = 0.10   # a made move: this share of the scene's x extent
REFLECTANCE_SCALE = 0.8
LIGHT_SCALE = 0.5


def _emits(o):
    return bool(np.any(np.asarray(o.emission) > 0))


def _area(o):
    """Sum of the polygons' areas (fan triangulation), to rank objects by size."""
    v = np.asarray(o.vertices, dtype=float)
    cv = np.asarray(o.corner_verts)
    total = 0.0
    for s, t in zip(np.asarray(o.loop_starts).tolist(), np.asarray(o.loop_totals).tolist()):
        p = v[cv[s:s + t]]
        total += 0.5 * np.linalg.norm(np.cross(p[1:-1] - p[0], p[2:] - p[0]), axis=1).sum()
    return total


def made_move(si):
    """For a scene without a stored move: (object, 4x4) translating its smallest non-emitting
    object along x by MADE_MOVE_SHARE of the scene's x extent, toward the side with room."""
    lo = np.min([np.min(o.vertices, axis=0) for o in si.objects], axis=0)
    hi = np.max([np.max(o.vertices, axis=0) for o in si.objects], axis=0)
    cands = [i for i, o in enumerate(si.objects) if not _emits(o)]
    i = min(cands, key=lambda k: (_area(si.objects[k]), k))
    dx = MADE_MOVE_SHARE * float(hi[0] - lo[0])
    if float(np.max(si.objects[i].vertices[:, 0])) + dx > hi[0]:
        dx = -dx
    m = np.eye(4)
    m[0, 3] = dx
    return i, m


def _corners(s, count):
    return np.concatenate([np.asarray(s.corner_radiance(i)).ravel() for i in range(count)]
                          or [np.zeros(0)])


class Stages:
    """One build's solver taken through the stages in order (up to and including `until`),
    keeping each stage's corners, what it did, its seconds and its update's mode."""

    def __init__(self, rn, solver, si, cluster_ids, until):
        self.rn, self.s, self.si, self.cluster_ids, self.until = rn, solver, si, cluster_ids, until
        self.count = len(si.objects)   # object ids to read corners from (an addition extends it)
        self.res, self.plan, self.seconds, self.modes = {}, {}, {}, {}
        self.skipped = []              # stages this module lacks the API for

    def wanted(self, name):
        return STAGES.index(name) <= STAGES.index(self.until)

    def has(self, name, *methods):
        """Whether `name` is to run and the module can: a stage it cannot is noted as skipped."""
        if not self.wanted(name):
            return False
        if all(hasattr(self.s, m) for m in methods):
            return True
        self.skipped.append(name)
        return False

    def stage(self, name, what, edit):
        """Runs `edit` (None: the full solve) then an update, and keeps the corners."""
        if not self.wanted(name):
            return
        t = time.perf_counter()
        if edit is None:
            self.s.solve()
        else:
            edit()
            self.s.update()
            stats = self.s.stats()
            mode = stats.get("mode", "?")
            if mode == "full" and stats.get("warnings"):   # why the update solved in full
                mode += " (" + "; ".join(stats["warnings"]) + ")"
            self.modes[name] = mode
        self.seconds[name] = time.perf_counter() - t
        self.res[name] = _corners(self.s, self.count)
        self.plan[name] = what

    def preview(self, moves, how):
        if not self.wanted("preview"):
            return
        t = time.perf_counter()
        patches, _ = self.s.preview(moves)
        self.seconds["preview"] = time.perf_counter() - t
        self.res["preview"] = np.concatenate(
            [np.concatenate([c.astype(np.float64), v.ravel()]) for _, (c, v) in sorted(patches.items())]
            or [np.zeros(0)])
        self.plan["preview"] = f"{self.names(moves)} ({how}) previewed"

    def names(self, ids):
        return ", ".join(self.si.objects[i].name for i in ids)

    def update(self, moves):
        def move():
            for i, m in moves.items():
                self.s.move_object(i, np.ascontiguousarray(m))
        self.stage("update", f"{self.names(moves)} moved", move)

    def material(self, moves):
        objs = self.si.objects
        cands = [i for i, o in enumerate(objs) if not _emits(o) and i not in moves]
        if not cands or not self.has("material", "set_reflectance"):
            return
        k = max(cands, key=lambda j: (_area(objs[j]), -j))
        rho = np.ascontiguousarray(np.asarray(objs[k].reflectance, dtype=np.float64) * REFLECTANCE_SCALE)
        self.stage("material", f"{objs[k].name} reflectance x {REFLECTANCE_SCALE}",
                   lambda: self.s.set_reflectance(k, rho))

    def remove_add(self, moved):
        if not self.has("remove", "remove_object", "add_object"):
            return
        from radiosity.core import scene_data
        o = self.si.objects[moved]
        self.stage("remove", f"{o.name} removed", lambda: self.s.remove_object(moved))

        def add():
            cid = self.cluster_ids[o.cluster] if o.cluster >= 0 else -1
            self.count = max(self.count, scene_data.add_native_object(self.s, o, cid) + 1)
        self.stage("add", f"{o.name} added back where it stood before the move (new id)", add)

    def light(self):
        if not self.si.lights or not self.has("light", "set_light"):
            return
        from radiosity.core import lights as core_lights

        def lights():
            for i, li in enumerate(self.si.lights):
                scaled = tuple(LIGHT_SCALE * float(x) for x in li.intensity)
                self.s.set_light(i, core_lights.to_native(self.rn, dataclasses.replace(li, intensity=scaled)))
        self.stage("light", f"{len(self.si.lights)} lights' intensity x {LIGHT_SCALE}", lights)

    def emission(self, moved):
        emitters = [i for i, o in enumerate(self.si.objects) if _emits(o) and i != moved]
        if not emitters or not self.has("emission", "set_emission"):
            return

        def emission():
            for i in emitters:
                e = np.asarray(self.si.objects[i].emission, dtype=np.float64) * LIGHT_SCALE
                self.s.set_emission(i, np.ascontiguousarray(e))
        self.stage("emission", f"{self.names(emitters)} emission x {LIGHT_SCALE}", emission)


def run_one(npz, preset, seed, until, out):
    """In a child process whose RADIOSITY_NATIVE_DIR names the build: the stages in order, up
    to and including `until`."""
    sys.path.insert(0, os.path.join(ROOT, "bench"))
    sys.path.insert(0, os.path.join(ROOT, "addon"))
    sys.path.insert(0, os.environ["RADIOSITY_NATIVE_DIR"])
    import radiosity_native as rn
    import accuracy_native
    from radiosity.core import scene_data
    z = np.load(npz)
    si, _ = accuracy_native.scene_input(z)
    scene, cluster_ids, _ = scene_data.build_native_scene(rn, si)
    st = rn.Settings.preset(preset)
    st.seed = seed
    run = Stages(rn, rn.Solver(scene, st), si, cluster_ids, until)
    run.stage("solve", f"full solve, {preset}, seed {seed}", None)
    if "move_ids" in z.files:
        moves = {int(i): np.array(m, dtype=float) for i, m in zip(z["move_ids"].tolist(), z["move_deltas"])}
        how = "stored move"
    else:
        i, m = made_move(si)
        moves = {i: m}
        how = f"made move: x {m[0, 3]:+.4g}"
    run.preview(moves, how)
    run.update(moves)
    moved = min(moves)
    run.material(moves)
    run.remove_add(moved)
    run.light()
    run.emission(moved)
    meta = {"plan": run.plan, "seconds": run.seconds, "modes": run.modes, "skipped": run.skipped}
    np.savez(out, _meta=np.array(json.dumps(meta)), **run.res)


def compare(label, got):
    """Prints each stage's comparison; True when any differs or only one build ran it."""
    differ = False
    meta = {k: json.loads(str(got[k]["_meta"])) for k in got}
    plan = meta["A"]["plan"] or meta["B"]["plan"]
    before = None   # build A's previous corners: whether the edit changed any
    for stage in STAGES:
        have = [k for k in ("A", "B") if stage in got[k].files]
        if not have:
            continue
        if len(have) == 1:
            print(f"{label} {stage}: only {have[0]} ran it ({plan.get(stage, '')})")
            differ = True
            continue
        x, y = got["A"][stage], got["B"][stage]
        mode = meta["A"]["modes"].get(stage)
        note = f"{meta['A']['plan'][stage]}" + (f"; {mode}" if mode else "")
        if stage != "preview":
            if before is not None and before.shape == x.shape:
                note += f"; changes {int(np.count_nonzero(x != before))}"
            before = x
        if x.shape != y.shape:
            print(f"{label} {stage}: {x.size} values against {y.size} [{note}]")
            differ = True
            continue
        bad = int(np.count_nonzero(x != y))
        worst = float(np.max(np.abs(x - y))) if x.size else 0.0
        print(f"{label} {stage}: {x.size} values, {bad} differ (largest difference {worst:.3g}) [{note}]")
        differ |= bad > 0
    for k in ("A", "B"):
        if meta[k]["skipped"]:
            print(f"{label}: build {k} lacks the API for {', '.join(meta[k]['skipped'])}")
    per = ", ".join(f"{k} {v:.1f}" for k, v in meta["A"]["seconds"].items())
    print(f"{label}: A {sum(meta['A']['seconds'].values()):.1f} s ({per}), "
          f"B {sum(meta['B']['seconds'].values()):.1f} s")
    return differ


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--a", required=True, help="directory of build A's radiosity_native module")
    ap.add_argument("--b", required=True, help="directory of build B's radiosity_native module")
    ap.add_argument("--presets", "--preset", default="MEDIUM", help="comma list, e.g. MEDIUM,HIGH")
    ap.add_argument("--seeds", "--seed", default="1", help="comma list of Settings.seed, e.g. 1,2")
    ap.add_argument("--until", choices=STAGES, default=STAGES[-1],
                    help="the last stage run (default: all; update: solve, preview and update only)")
    ap.add_argument("--child", nargs=2, help=argparse.SUPPRESS)
    ap.add_argument("scenes", nargs="*")
    a = ap.parse_args()
    presets = [p.strip() for p in a.presets.split(",") if p.strip()]
    seeds = [int(x) for x in a.seeds.split(",") if x.strip()]
    if a.child:
        run_one(a.child[0], presets[0], seeds[0], a.until, a.child[1])
        return 0
    sys.path.insert(0, os.path.join(ROOT, "bench"))
    import accuracy_native
    differ = False
    start = time.perf_counter()
    with tempfile.TemporaryDirectory() as tmp:
        for name in a.scenes or SCENES:
            npz = name if name.endswith(".npz") else accuracy_native.export(name, tmp)
            for preset in presets:
                for seed in seeds:
                    got = {}
                    for label, native in (("A", a.a), ("B", a.b)):
                        out = os.path.join(tmp, f"{os.path.basename(npz)}.{preset}.{seed}.{label}.npz")
                        env = dict(os.environ, RADIOSITY_NATIVE_DIR=os.path.abspath(native))
                        subprocess.run([sys.executable, os.path.abspath(__file__), "--a", a.a, "--b", a.b,
                                        "--presets", preset, "--seeds", str(seed), "--until", a.until,
                                        "--child", npz, out],
                                       check=True, env=env)
                        got[label] = np.load(out)
                    label = os.path.basename(name)[:-4] if name.endswith(".npz") else name
                    differ |= compare(f"{label} {preset} seed {seed}", got)
    print(f"{time.perf_counter() - start:.0f} s in all")
    print("different" if differ else "identical")
    return 1 if differ else 0


if __name__ == "__main__":
    sys.exit(main())
