#!/usr/bin/python3
"""Plot rockdem histories (HDF5, /history/<name>) to a PNG.

  plot_history.py OUT/history.h5 --list
  plot_history.py OUT/history.h5 -y shear_stress                      # vs time
  plot_history.py OUT/history.h5 -x shear_displacement:mm -y shear_stress:MPa -o curve.png
  plot_history.py OUT/history.h5 -y normal_stress:MPa -y shear_stress:MPa --last 5000

A series may be followed by ':UNIT' to convert its stored SI unit with a decimal prefix
(Pa -> kPa, MPa, GPa; m -> mm, um; s -> ms ...). The x axis defaults to time.
Uses the Debian python3-h5py and python3-matplotlib (run with /usr/bin/python3).
"""
import argparse
import sys

import h5py
import numpy as np

PREFIXES = {"G": 1e9, "M": 1e6, "k": 1e3, "": 1.0, "c": 1e-2, "m": 1e-3, "u": 1e-6, "µ": 1e-6, "n": 1e-9}


def load(path):
    try:
        # locking=False: the file may belong to a run that is still writing it
        f = h5py.File(path, "r", locking=False)
    except OSError as e:
        sys.exit(f"plot_history: cannot open '{path}': {e}")
    if "history" not in f:
        sys.exit(f"plot_history: '{path}' has no /history group (is it a rockdem history file?)")
    return f["history"]


def attr(ds, name):
    v = ds.attrs.get(name, "")
    return v.decode() if isinstance(v, bytes) else str(v)


def series(group, spec):
    """Values of 'name' or 'name:unit' converted to that unit, and an axis label."""
    name, _, want = spec.partition(":")
    if name not in group:
        valid = ", ".join(sorted(group.keys()))
        sys.exit(f"plot_history: no series '{name}'; the file has: {valid}")
    ds = group[name]
    unit = attr(ds, "unit")
    values = np.asarray(ds[...], dtype=float)
    if want and want != unit:
        prefix = want[: len(want) - len(unit)] if unit and want.endswith(unit) else None
        if prefix not in PREFIXES:
            sys.exit(f"plot_history: cannot convert '{name}' from '{unit or 'no unit'}' to '{want}'; "
                     f"use a decimal prefix of '{unit}' ({', '.join(p + unit for p in PREFIXES if p)})")
        values = values / PREFIXES[prefix]
        unit = want
    return values, f"{name} [{unit}]" if unit else name


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("file", help="history file written by rockdem (HDF5)")
    ap.add_argument("--list", action="store_true", help="print the series (name, unit, samples, description)")
    ap.add_argument("-x", default="time", help="series on the x axis, NAME[:UNIT] (default: time)")
    ap.add_argument("-y", action="append", default=[], help="series on the y axis, NAME[:UNIT]; repeatable")
    ap.add_argument("-o", "--output", help="PNG to write (default: <file stem>_<y>.png)")
    ap.add_argument("--last", type=int, default=0, help="plot only the last N samples")
    ap.add_argument("--title", default=None)
    args = ap.parse_args(argv)

    group = load(args.file)
    if args.list:
        names = ["time", "step"] + sorted(n for n in group.keys() if n not in ("time", "step"))
        width = max(len(n) for n in names)
        for n in names:
            ds = group[n]
            unit = f"[{attr(ds, 'unit')}]" if attr(ds, "unit") else "-"
            print(f"{n:<{width}}  {unit:<6}  {ds.shape[0]} samples  {attr(ds, 'description')}")
        return 0
    if not args.y:
        ap.error("give at least one -y SERIES (see --list)")

    import matplotlib
    matplotlib.use("Agg")  # no display needed
    import matplotlib.pyplot as plt

    x, xlabel = series(group, args.x)
    fig, ax = plt.subplots(figsize=(7, 4.5), dpi=120)
    ylabels = []
    for spec in args.y:
        y, ylabel = series(group, spec)
        xs, ys = (x[-args.last:], y[-args.last:]) if args.last > 0 else (x, y)
        ax.plot(xs, ys, label=ylabel, linewidth=1.2)
        ylabels.append(ylabel)
    ax.set_xlabel(xlabel)
    ax.set_ylabel(ylabels[0] if len(ylabels) == 1 else "")
    if len(ylabels) > 1:
        ax.legend()
    ax.grid(True, alpha=0.3)
    if args.title:
        ax.set_title(args.title)
    fig.tight_layout()
    out = args.output
    if not out:
        stem = args.file[:-3] if args.file.endswith(".h5") else args.file
        out = f"{stem}_{'_'.join(s.partition(':')[0] for s in args.y)}.png"
    fig.savefig(out)
    print(f"plot_history: wrote {out}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
