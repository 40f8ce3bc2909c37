#!/usr/bin/python3
"""How far a run's response is from its own mirror image about x = 0, stage by stage.

For a model that is its own mirror image (cases/drift/symmetric.toml, from
scripts/make-symmetric-drift) under a vertical input, every gridpoint's displacement must mirror
its partner's: u_x(-x, y) = -u_x(x, y), u_y(-x, y) = u_y(x, y). For each stage checkpoint
(stage_<n>_<name>.h5) this pairs every block with the block whose initial centroid is its mirror
image, every gridpoint with the mirrored one of that block, and prints the largest difference,
the largest displacement and their ratio (issue 14 asks for 1e-9).

Usage: /usr/bin/python3 scripts/mirror_difference.py RUN_DIR
"""
import glob
import sys

import h5py
import numpy as np


def mirror_difference(path):
    with h5py.File(path, "r", locking=False) as f:
        x0, x = f["gridpoints/x0"][:], f["gridpoints/x"][:]
        first, count = f["blocks/first_gp"][:], f["blocks/n_gp"][:]
    u = x - x0
    centroid = np.array([x0[a:a + n].mean(axis=0) for a, n in zip(first, count)])
    index = {(round(c[0], 9) + 0.0, round(c[1], 9)): b for b, c in enumerate(centroid)}
    worst = 0.0
    for b, c in enumerate(centroid):
        m = index.get((round(-c[0], 9) + 0.0, round(c[1], 9)))
        if m is None:
            raise SystemExit(f"{path}: block {b} at ({c[0]:.6g}, {c[1]:.6g}) has no mirror image: the model is not symmetric")
        partners = np.arange(first[m], first[m] + count[m])
        for g in range(first[b], first[b] + count[b]):
            d = np.hypot(x0[partners, 0] + x0[g, 0], x0[partners, 1] - x0[g, 1])
            if d.min() > 1e-9:
                raise SystemExit(f"{path}: gridpoint {g} has no mirror image in block {m}")
            h = partners[d.argmin()]
            worst = max(worst, abs(u[g, 0] + u[h, 0]), abs(u[g, 1] - u[h, 1]))
    return worst, np.abs(u).max()


def main(argv):
    if len(argv) != 2 or argv[1] in ("-h", "--help"):
        print(__doc__.strip())
        return 0 if len(argv) == 2 else 2
    paths = sorted(glob.glob(argv[1] + "/stage_*.h5"), key=lambda p: int(p.rsplit("/", 1)[1].split("_")[1]))
    if not paths:
        print(f"mirror_difference.py: no stage checkpoints (stage_<n>_<name>.h5) in {argv[1]}", file=sys.stderr)
        return 2
    print(f"{'stage':<28} {'mirror difference':>18} {'largest displacement':>21} {'relative':>9}")
    for p in paths:
        e, s = mirror_difference(p)
        print(f"{p.rsplit('/', 1)[1]:<28} {e:16.3e} m {s:19.3e} m {e / s if s > 0 else 0.0:9.2e}")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
