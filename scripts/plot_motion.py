#!/usr/bin/python3
"""Plot the ground motion a stage applied (rockdem's <out>/motion_<n>_<stage>.csv).

Usage: /usr/bin/python3 scripts/plot_motion.py motion_2_event1.csv [-o motion_2_event1.png]

Three panels sharing the time axis: acceleration, velocity and displacement of every motion in
the file, after processing and the stage's scale, as the boundary applied them. The title names
the stage; the legend, each motion's direction, peak values and stage factor.
"""
import argparse
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def read(path):
    meta, header, rows = [], None, []
    with open(path) as f:
        for line in f:
            if line.startswith("#"):
                meta.append(line[1:].strip())
            elif header is None:
                header = line.strip().split(",")
            elif line.strip():
                rows.append([float(x) for x in line.split(",")])
    if header is None or not rows:
        raise SystemExit(f"{path}: no data rows")
    cols = list(zip(*rows))
    return meta, header, {h: cols[i] for i, h in enumerate(header)}


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("csv")
    ap.add_argument("-o", "--out", help="PNG to write (default: beside the CSV)")
    a = ap.parse_args()
    meta, header, data = read(a.csv)
    motions = [h[: -len("_acc_mps2")] for h in header if h.endswith("_acc_mps2")]
    info = {}
    for m in meta:
        if m.startswith("motion: "):
            parts = dict(p.split(": ", 1) for p in m.split(" | ") if ": " in p)
            info[parts.get("motion")] = parts
    stage = meta[0].split("'")[1] if meta and "'" in meta[0] else os.path.basename(a.csv)
    fig, ax = plt.subplots(3, 1, sharex=True, figsize=(8, 7))
    t = data["time_s"]
    for m in motions:
        p = info.get(m, {})
        label = f"{m} ({p.get('direction', '?')}, x{float(p.get('stage factor', 'nan')):.3g})"
        ax[0].plot(t, data[m + "_acc_mps2"], lw=0.8, label=label)
        ax[1].plot(t, data[m + "_vel_mps"], lw=0.8, label=label)
        ax[2].plot(t, data[m + "_disp_m"], lw=0.8, label=label)
    ax[0].set_ylabel("acceleration (m/s²)")
    ax[1].set_ylabel("velocity (m/s)")
    ax[2].set_ylabel("displacement (m)")
    ax[2].set_xlabel("time from the stage start (s)")
    for x in ax:
        x.grid(alpha=0.3)
        x.axhline(0, color="k", lw=0.5)
    ax[0].legend(loc="upper right", fontsize=8)
    ax[0].set_title(f"Ground motion applied in stage '{stage}'")
    fig.tight_layout()
    out = a.out or os.path.splitext(a.csv)[0] + ".png"
    fig.savefig(out, dpi=110)
    return 0


if __name__ == "__main__":
    sys.exit(main())
