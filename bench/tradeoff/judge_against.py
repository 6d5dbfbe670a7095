"""Judge saved corners (bench/accuracy_native.py --save) against a reference made in parts
(bench/tradeoff/bsdf_ref.py), beside the cached reference of the scene: rRMSE over every corner
but emitters' (bench/corner_metric.py), with the reference's own noise removed in quadrature
(its per-corner variance from the spread of its parts), and the mean ours / reference.

    python3 bench/tradeoff/judge_against.py SCENE REF_PARTS.npz SAVED.npz [SAVED.npz ...]
"""
import os
import sys

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.dirname(HERE))
sys.path.insert(0, HERE)
import corner_metric as cm  # noqa: E402
import scenes as bt_scenes  # noqa: E402


def main():
    scene, parts_path, saved = sys.argv[1], sys.argv[2], sys.argv[3:]
    cached, cached_var, _ = cm.load_reference(bt_scenes.ref(scene))
    parts = np.load(parts_path)["parts"]
    k = len(parts)
    ref, var = cm.combine_parts(parts, np.ones(k))  # equal samples per part
    for path in saved:
        z = np.load(path)
        x, emit = z["corners"].astype(np.float64), z["emitter"]
        if x.shape != ref.shape:
            raise SystemExit(f"{path}: {x.shape[0]} corners, the reference has {ref.shape[0]}")
        a = cm.corner_error(x, cached, emitter=emit, ref_var=cached_var)
        b = cm.corner_error(x, ref, emitter=emit, ref_var=var)
        print(f"{os.path.basename(path)}: cached reference rRMSE {a['rrmse']:.4f} (noise removed "
              f"{a.get('rrmse_denoised', float('nan')):.4f}), mean {a['mean_ratio']:.4f} | "
              f"{os.path.basename(parts_path)} ({k} parts) rRMSE {b['rrmse']:.4f} (noise removed "
              f"{b.get('rrmse_denoised', float('nan')):.4f}, its noise {b.get('ref_noise_rrmse', float('nan')):.4f}), "
              f"mean {b['mean_ratio']:.4f}")
    e = cm.corner_error(ref, cached, emitter=z["emitter"], ref_var=cached_var)
    print(f"the parts' mean against the cached reference: rRMSE {e['rrmse']:.4f}, mean {e['mean_ratio']:.4f}")


if __name__ == "__main__":
    main()
