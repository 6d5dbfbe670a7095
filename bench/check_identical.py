#!/usr/bin/env python3
"""Do two builds of the native module give the same results? For changes that must not change
the solution (speed work): runs a room with two boxes in a collection, with and without lights
(point, spot), at DRAFT and MEDIUM, through a solve, two moves, dimming the lamp, a reflectance
change and a light change, and saves every output (corner radiance and irradiance of every
object, element/link/ray/iteration counts) after each step.

    python3 bench/check_identical.py save <build-before>/native /tmp/before.npz
    python3 bench/check_identical.py save build/native /tmp/after.npz
    python3 bench/check_identical.py compare /tmp/before.npz /tmp/after.npz
"""
import os
import sys

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))


def save(module_dir, path):
    sys.path.insert(0, os.path.abspath(module_dir))
    sys.path.insert(0, os.path.join(HERE, "..", "tests", "python"))
    import radiosity_native as rn
    import radtest_scenes as S

    out = {}

    def dump(tag, s, nobj):
        st = s.stats()
        for k in ("elements", "links", "rays", "iterations", "history_links", "cluster_links"):
            out[f"{tag}/{k}"] = np.array([st[k]])
        for o in range(nobj):
            out[f"{tag}/rad{o}"] = np.asarray(s.corner_radiance(o))
            out[f"{tag}/irr{o}"] = np.asarray(s.corner_irradiance(o))

    def light(kind, **kw):
        L = rn.Light()
        L.name = kind
        L.type = getattr(rn.LightType, kind)
        for k, v in kw.items():
            setattr(L, k, v)
        return L

    for with_lights in (False, True):
        for preset in ("DRAFT", "MEDIUM"):
            sc = rn.Scene()
            S.box([0, 0, 0], [4, 4, 3], 4, inward=True).add(sc, "room", rho=0.6)
            S.square(2, 2, 2.99, 1.0, facing_up=False).add(sc, "lamp", rho=0.0, emission=2.0 if with_lights else 8.0)
            c = sc.add_cluster("Boxes")
            S.box([0.8, 0.8, 0], [1.6, 1.6, 0.8], 2).add(sc, "box1", cluster=c, rho=(0.7, 0.3, 0.2))
            S.box([2.5, 2.2, 0], [3.2, 3.4, 1.2], 2).add(sc, "box2", cluster=c, rho=(0.2, 0.4, 0.7))
            if with_lights:
                sc.add_light(light("POINT", position=(1.0, 3.0, 2.5), radius=0.1, intensity=(3.0, 3.0, 3.0)))
                sc.add_light(light("SPOT", position=(3.0, 1.0, 2.8), direction=(0, 0, -1), spot_size=1.0,
                                   spot_blend=0.2, intensity=(2.0, 2.0, 2.0)))
            s = rn.Solver(sc, rn.Settings.preset(preset))
            tag = f"{'lights' if with_lights else 'plain'}_{preset}"
            s.solve()
            dump(tag + "/solve", s, 4)
            m = np.eye(4)
            m[0, 3], m[1, 3] = 0.9, 0.7
            s.move_object(2, m)
            s.update()
            dump(tag + "/move", s, 4)
            m[0, 3] = 1.0
            s.move_object(2, m)
            m3 = np.eye(4)
            m3[1, 3] = -0.3
            s.move_object(3, m3)
            s.update()
            dump(tag + "/move2", s, 4)
            s.set_emission(1, np.array([1.0, 1.0, 1.0]))
            s.update()
            dump(tag + "/dim", s, 4)
            s.set_reflectance(0, np.array([0.3, 0.5, 0.4]))
            s.update()
            dump(tag + "/rho", s, 4)
            if with_lights:
                s.set_light(0, light("POINT", position=(2.0, 2.0, 2.0), radius=0.0, intensity=(1.0, 2.0, 3.0)))
                s.update()
                dump(tag + "/light", s, 4)
    np.savez(path, **out)
    print(f"saved {len(out)} arrays from {rn.__file__}")


def compare(a_path, b_path):
    a, b = np.load(a_path), np.load(b_path)
    if sorted(a.files) != sorted(b.files):
        print("different outputs saved")
        return 1
    bad = [k for k in a.files if a[k].shape != b[k].shape or not np.array_equal(a[k], b[k])]
    for k in bad[:20]:
        x, y = a[k].astype(float), b[k].astype(float)
        err = np.sqrt(np.mean((x - y) ** 2)) / max(1e-30, np.sqrt(np.mean(x ** 2))) if x.shape == y.shape else None
        print("differs:", k, "NRMSE", err)
    print(f"{len(a.files) - len(bad)} of {len(a.files)} arrays bit-identical")
    return 1 if bad else 0


if __name__ == "__main__":
    if len(sys.argv) == 4 and sys.argv[1] == "save":
        save(sys.argv[2], sys.argv[3])
    elif len(sys.argv) == 4 and sys.argv[1] == "compare":
        sys.exit(compare(sys.argv[2], sys.argv[3]))
    else:
        print(__doc__)
        sys.exit(2)
