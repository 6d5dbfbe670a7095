"""Where an interior's error against Cycles lies: one bake through the add-on, judged per object.

Runs in PyPI's bpy (python3) or Blender (blender -b --python); needs a scene and its Cycles
reference as bench/interior/run_interior.py --cycles caches them:

    python3 bench/interior/per_object.py -- SCENE.blend SCENE_cycles5.npz build/radiosity.zip MEDIUM \
        [--corners NAME ...]

Per object (mesh objects sorted by name, the reference's order): its corners, its share of the
scene's squared relative error and the reference noise's share of it (both over the scene's
total, bench/corner_metric.py's floor), its mean ours / reference, and its rRMSE. With
--corners, every corner of the named objects: position (the original mesh's vertex), ours,
the reference and the reference's standard deviation.
"""
import os
import sys

import bpy
import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "tradeoff"))
sys.path.insert(0, os.path.join(HERE, ".."))
import bt_common as bt  # noqa: E402
import corner_metric as cm  # noqa: E402


def main():
    argv = sys.argv[sys.argv.index("--") + 1:]
    blend, ref_path, zip_path, preset = argv[:4]
    show = argv[argv.index("--corners") + 1:] if "--corners" in argv else []
    bpy.ops.wm.open_mainfile(filepath=os.path.abspath(blend))
    bt.install_addon(zip_path)
    scene = bpy.context.scene
    scene.radiosity.preset = preset
    bpy.ops.radiosity.bake()
    objs = bt.mesh_objects(scene)
    names = [o.name for o in objs]
    x = bt.all_corners(objs, bt.ATTR_OURS).astype(np.float64)
    emit = bt.emitter_mask(objs)
    owner, _ = bt.corner_owner(objs)
    pos = bt.corner_positions(objs)
    z = np.load(ref_path, allow_pickle=True)
    ref, var = z["corners"].astype(np.float64), z["corners_var"].astype(np.float64)
    e = cm.corner_error(x, ref, emitter=emit, ref_var=var)
    print(f"scene: rRMSE {e['rrmse']:.4f} (reference noise removed {e['rrmse_denoised']:.4f}), "
          f"NRMSE {e['nrmse']:.4f}, mean ours/ref {e['mean_ratio']:.4f}")
    den = np.maximum(ref, cm.scene_floor(ref, emit))
    judged = ~emit
    rel2 = (((x - ref) / den) ** 2).mean(axis=1)
    noise2 = (var / den ** 2).mean(axis=1)
    total = rel2[judged].sum()
    print("| object | corners | share of error | of it reference noise | ours / ref | rRMSE |")
    print("|---|---|---|---|---|---|")
    for k in sorted(range(len(names)), key=lambda k: -rel2[(owner == k) & judged].sum()):
        m = (owner == k) & judged
        if not m.any():
            continue
        print(f"| {names[k]} | {int(m.sum())} | {100 * rel2[m].sum() / total:.1f} % | "
              f"{100 * noise2[m].sum() / total:.1f} % | {x[m].mean() / max(ref[m].mean(), 1e-30):.3f} | "
              f"{np.sqrt(rel2[m].mean()):.3f} |")
    for name in show:
        k = names.index(name)
        print(name)
        for i in np.where(owner == k)[0]:
            print(f"   {np.round(pos[i], 3)}  ours {x[i].mean():.4f}  ref {ref[i].mean():.4f} "
                  f"(sd {np.sqrt(var[i].mean()):.4f})")


main()
