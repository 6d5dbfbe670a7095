"""The contact test's floor corners natively, for several seeds: a quick check of near-field
changes without Blender's bake (tests/blender/test_corner_exact.py's contact test judges one
seed per flavour; this shows the spread).

    python3 bench/contact_corner.py [--preset HIGH] [--seeds 1,2,3,4] [--native-dir DIR]
                                    [--set NAME=VALUE ...] [--npz SCENE.npz]

The scene (corner_scenes.build_contact: a box standing on a gridded floor, a quad lamp) is
exported once through bench/export_scene.py in Debian's Blender unless --npz names an export.
Each seed prints, against both cached Cycles references (tests/blender/data/corner_contact_v3
and _v4: Blender 3.4 and 5.x), the worst floor corner on the box's footprint edge as the test
measures it, |x - r| / max(r, 0.05 mean r) (the test's bound is 0.1), where it is, and the
scene's rays.
"""
import argparse
import os
import subprocess
import sys
import tempfile

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
sys.path.insert(0, HERE)
sys.path.insert(0, os.path.join(HERE, "tradeoff"))
sys.path.insert(0, os.path.join(ROOT, "addon"))
DATA = os.path.join(ROOT, "tests", "blender", "data")

EXPORT = """
import sys, os
for p in ["tests/blender", "tests/blender/scripts", "bench"]:
    sys.path.insert(0, os.path.join({root!r}, p))
import bpy
bpy.ops.wm.read_factory_settings(use_empty=True)
import corner_scenes
corner_scenes.build_contact()
sys.argv = ["export_scene", "--", {out!r}]
import export_scene  # writes the .npz on import
"""


def export(tmp):
    import bt_run
    out = os.path.join(tmp, "contact.npz")
    script = os.path.join(tmp, "export_contact.py")
    with open(script, "w") as f:
        f.write(EXPORT.format(root=ROOT, out=out))
    env = dict(os.environ, PATH=bt_run.path_without_pyenv(os.environ.get("PATH", "")), PYTHONDONTWRITEBYTECODE="1")
    proc = subprocess.run([bt_run.blender_exe(), "-b", "--factory-startup", "--python-exit-code", "1",
                           "--python", script], env=env, capture_output=True, text=True)
    if proc.returncode != 0 or not os.path.exists(out):
        raise SystemExit(f"exporting the contact scene failed:\n{(proc.stdout + proc.stderr)[-3000:]}")
    return out


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--preset", default="HIGH")
    ap.add_argument("--seeds", default="1,2,3,4")
    ap.add_argument("--native-dir", default=os.path.join(ROOT, "build", "native"))
    ap.add_argument("--set", action="append", default=[], metavar="NAME=VALUE")
    ap.add_argument("--npz")
    a = ap.parse_args()
    sys.path.insert(0, a.native_dir)
    import radiosity_native as rn
    import accuracy_native as an
    from radiosity.core import scene_data
    path = a.npz or export(tempfile.mkdtemp(prefix="contact-corner-"))
    z = np.load(path)
    si, _ = an.scene_input(z)
    names = [o.name for o in si.objects]
    fl = names.index("Floor")
    pos = z[f"o{fl}_vertices"][z[f"o{fl}_corner_verts"]]
    lo, hi = np.array([-0.3, -0.5]), np.array([0.5, 0.3])     # corner_scenes.CONTACT_BOX_LO/HI

    def inside(xy, closed):
        m = 1e-6 if closed else -1e-6
        return np.all((xy >= lo - m) & (xy <= hi + m), axis=1)

    line = inside(pos[:, :2], True) & ~inside(pos[:, :2], False)
    n_floor = len(pos)
    refs = {t: np.load(os.path.join(DATA, f"corner_contact_{t}.npy"))[0][:n_floor] for t in ("v3", "v4")}
    print(f"module: {rn.__file__}; {a.preset}; {int(line.sum())} contact-line corners", flush=True)
    for seed in [int(x) for x in a.seeds.split(",")]:
        st = rn.Settings.preset(a.preset)
        st.seed = seed
        for kv in a.set:
            k, v = kv.split("=", 1)
            setattr(st, k, type(getattr(st, k))(v))
        scene, _, oids = scene_data.build_native_scene(rn, si)
        s = rn.Solver(scene, st)
        s.solve()
        x = np.asarray(s.corner_radiance(oids[fl]), dtype=np.float64)
        if si.objects[fl].corner_perm is not None:
            x = x[si.objects[fl].corner_perm]
        parts = []
        for tag, ref in refs.items():
            rel = np.abs(x - ref) / np.maximum(ref, 0.05 * ref.mean())
            i = int(np.argmax(rel.max(axis=1) * line))
            parts.append(f"{tag}: worst {rel[line].max():.3f} at ({pos[i][0]:+.2f}, {pos[i][1]:+.2f}) "
                         f"x {x[i, 0]:.5f} ref {ref[i, 0]:.5f}")
        print(f"seed {seed}: " + " | ".join(parts) + f"; rays {s.stats().get('rays', 0):,}", flush=True)


if __name__ == "__main__":
    main()
