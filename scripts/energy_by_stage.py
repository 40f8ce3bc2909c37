#!/usr/bin/python3
"""The energy balance stage by stage, from a run's history.h5: for each stage, the change of every
term of the `energy` history over the stage (its first to its last sample) and the closure, the
change of the imbalance over the largest change of a term (docs/engine.md#energy-balance).

The run must record the components as histories named <prefix><component> (default prefix
"energy_"), e.g.
    [[histories]]
    name = "energy_kinetic"
    quantity = "energy"
    component = "kinetic"
for kinetic, strain, contact, gravity_work, boundary_work, slip, damping and imbalance, and, if
recorded, refresh (the contacts' elastic energy the contact refreshes changed, part of the
imbalance): then two more columns, refresh and the closure of imbalance + refresh.

Usage: /usr/bin/python3 scripts/energy_by_stage.py RUN_DIR [--prefix PREFIX]
"""
import sys

import h5py
import numpy as np

TERMS = ("kinetic", "strain", "contact", "gravity_work", "boundary_work", "slip", "damping")


def stage_changes(run_dir, prefix="energy_"):
    """Per stage, in order: (stage, the change of each recorded term over it, the largest change of
    a term, the closure, and with `refresh` recorded the closure of imbalance + refresh, else
    None). Raises KeyError naming the histories the run lacks."""
    with h5py.File(run_dir + "/history.h5", "r", locking=False) as f:
        h = f["history"]
        missing = [t for t in TERMS + ("imbalance",) if prefix + t not in h]
        if missing:
            raise KeyError(", ".join(prefix + t for t in missing))
        stage = h["stage"][:]
        names = TERMS + ("imbalance",) + (("refresh",) if prefix + "refresh" in h else ())
        e = {t: h[prefix + t][:] for t in names}
    out = []
    for s in sorted(set(stage.tolist())):
        idx = np.where(stage == s)[0]
        d = {t: e[t][idx[-1]] - e[t][idx[0]] for t in e}
        scale = max(abs(d[t]) for t in TERMS)
        closure = abs(d["imbalance"]) / scale if scale > 0 else 0.0
        without = (abs(d["imbalance"] + d["refresh"]) / scale if scale > 0 else 0.0) if "refresh" in d else None
        out.append((int(s), d, scale, closure, without))
    return out


def main(argv):
    if len(argv) < 2 or argv[1] in ("-h", "--help"):
        print(__doc__.strip())
        return 0 if len(argv) >= 2 else 2
    prefix = argv[argv.index("--prefix") + 1] if "--prefix" in argv else "energy_"
    try:
        rows = stage_changes(argv[1], prefix)
    except KeyError as e:
        print(f"energy_by_stage.py: {argv[1]}/history.h5 lacks {e.args[0]}", file=sys.stderr)
        return 2
    refresh = bool(rows) and rows[0][4] is not None
    print("stage  " + "  ".join(f"{t:>13}" for t in TERMS) + "      imbalance  closure" +
          ("        refresh  without" if refresh else ""))
    for s, d, _, closure, without in rows:
        line = f"{s:5d}  " + "  ".join(f"{d[t]:13.4g}" for t in TERMS) + f"  {d['imbalance']:13.4g}  {closure:7.2%}"
        if refresh:
            line += f"  {d['refresh']:13.4g}  {without:7.2%}"
        print(line)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
