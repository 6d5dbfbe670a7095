"""How far one solve of an interior is from another (a cheaper setting against a costlier one,
e.g. MEDIUM against HIGH as a stand-in for a converged reference where none exists):

    python3 bench/interior/solve_native.py F.npz HIGH --save /tmp/high.npz
    python3 bench/interior/solve_native.py F.npz MEDIUM --save /tmp/medium.npz
    python3 bench/interior/compare_solves.py /tmp/high.npz /tmp/medium.npz [/tmp/other.npz ...]

Per compared solve, over the corners of every written object: the relative RMS error (each
corner's difference over the first solve's value at it, that value floored at a tenth of its
object's mean so that a corner in a contact shadow does not weigh without end), its per-object
NRMSE (RMS difference over the object's mean) as the median and the worst over the objects,
and the mean ratio (bias). Max channel of each corner.
"""
import sys

import numpy as np


def objects(path):
    z = np.load(path)
    return {k: z[k].reshape(-1, 3).max(axis=1).astype(np.float64) for k in z.files}


def main():
    ref = objects(sys.argv[1])
    for path in sys.argv[2:]:
        got = objects(path)
        rel, per, sums = [], [], [0.0, 0.0]
        for k, r in ref.items():
            v = got.get(k)
            if v is None or v.shape != r.shape or r.size == 0:
                print(f"{path}: object {k} differs in its corners")
                break
            mean = r.mean()
            if not mean > 0:
                continue
            d = v - r
            rel.append(d / np.maximum(r, 0.1 * mean))
            per.append(np.sqrt(np.mean(d * d)) / mean)
            sums[0] += v.sum()
            sums[1] += r.sum()
        else:
            rel = np.concatenate(rel)
            print(f"{path}: relative RMS {100 * np.sqrt(np.mean(rel * rel)):.2f} %, per-object NRMSE "
                  f"median {100 * np.median(per):.2f} % worst {100 * np.max(per):.2f} %, mean ratio "
                  f"{sums[0] / sums[1]:.4f}")


if __name__ == "__main__":
    main()
