#!/usr/bin/python3
"""Model against measurement for one direct-shear test, like the CNWRA report's Figures 5-1..5-44.

  plot_compare.py MEASURED.csv MODEL.csv -o FIGURE.png [--title TEXT]

Two panels: shear stress [MPa] and normal displacement [mm], both against shear displacement
[mm]; the measurement in solid lines, the model dashed, one colour per stage (shades of it for
successive cycles, darker = later). Both files are in the measurement format
(shared/docs/measurement-format.md). Run with Debian's /usr/bin/python3 (python3-matplotlib);
`rockdem compare --plot DIR` calls it so.
"""
import argparse
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

COLUMNS = ("time_s", "stage", "normal_stress_MPa", "shear_disp_mm", "shear_stress_MPa", "normal_disp_mm")
STAGE_MAPS = ("Blues", "Oranges", "Greens", "Reds", "Purples", "Greys")


def read_record(path):
    """Metadata dict and a dict of numpy columns; stops with file:line on a broken line."""
    meta, header, rows = {}, None, []
    try:
        fh = open(path, encoding="utf-8")
    except OSError as e:
        sys.exit(f"plot_compare: cannot open '{path}': {e.strerror}")
    with fh:
        for lineno, line in enumerate(fh, 1):
            s = line.strip()
            if not s:
                continue
            if s.startswith("#") and header is None:
                key, _, value = s[1:].partition(":")
                meta[key.strip()] = value.strip()
                continue
            fields = [x.strip() for x in s.split(",")]
            if header is None:
                header = fields
                missing = [c for c in COLUMNS if c not in header]
                if missing:
                    sys.exit(f"plot_compare: {path}:{lineno}: missing column(s) {', '.join(missing)}")
                continue
            if len(fields) != len(header):
                sys.exit(f"plot_compare: {path}:{lineno}: {len(fields)} fields, the header has {len(header)}")
            try:
                rows.append([float(x) for x in fields])
            except ValueError:
                sys.exit(f"plot_compare: {path}:{lineno}: non-numeric value")
    if header is None or not rows:
        sys.exit(f"plot_compare: {path}: no header or no data rows")
    data = np.asarray(rows)
    return meta, {c: data[:, header.index(c)] for c in COLUMNS}


def cycle_starts(u):
    """Row indices where cycles begin: leaving the origin on the first stroke's side after having
    come back to it (hysteresis of 2 % of the range against noise), as rockdem compare counts them."""
    h = 0.02 * (u.max() - u.min()) if len(u) else 0.0
    if h <= 0:
        return [0]
    beyond = np.nonzero(np.abs(u) > h)[0]
    side = np.sign(u[beyond[0]]) if len(beyond) else 1.0
    starts, left, returned, home = [0], False, False, 0
    for i, x in enumerate(side * u):
        if x <= h:
            home = i
            returned = returned or left
            left = False
        elif x > 2.0 * h:
            if returned:
                starts.append(home)
                returned = False
            left = True
    return starts


def pieces(rec):
    """(stage, cycle, index array) for every stage and cycle, in file order."""
    out = []
    stage = rec["stage"].astype(int)
    for s in np.unique(stage):
        idx = np.nonzero(stage == s)[0]
        starts = cycle_starts(rec["shear_disp_mm"][idx]) + [len(idx) - 1]
        for c in range(len(starts) - 1):
            out.append((int(s), c + 1, idx[starts[c]:starts[c + 1] + 1]))
    return out


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[1])
    ap.add_argument("measured")
    ap.add_argument("model")
    ap.add_argument("-o", "--out", required=True, help="PNG file")
    ap.add_argument("--title", help="figure title (default: specimen and joint model from the files)")
    a = ap.parse_args()
    mmeta, meas = read_record(a.measured)
    dmeta, model = read_record(a.model)

    fig, axes = plt.subplots(1, 2, figsize=(13, 5.2), constrained_layout=True)
    stages = sorted(set(meas["stage"].astype(int)) | set(model["stage"].astype(int)))
    handles = {}
    for rec, style, who in ((meas, "-", "measured"), (model, "--", "model")):
        parts = pieces(rec)
        ncyc = {}
        for s, c, _ in parts:
            ncyc[s] = max(ncyc.get(s, 0), c)
        for s, c, idx in parts:
            cmap = plt.get_cmap(STAGE_MAPS[stages.index(s) % len(STAGE_MAPS)])
            shade = 0.85 if ncyc[s] == 1 else 0.45 + 0.5 * (c - 1) / (ncyc[s] - 1)
            colour = cmap(shade)
            sn = np.median(meas["normal_stress_MPa"][meas["stage"] == s]) if np.any(meas["stage"] == s) else np.nan
            label = f"{who}, stage {s} ({sn:.3g} MPa)" if len(stages) > 1 else who
            if ncyc[s] > 1:
                label += f", cycles 1-{ncyc[s]}"
            lw = 1.3 if who == "measured" else 1.6
            for ax, y in zip(axes, ("shear_stress_MPa", "normal_disp_mm")):
                (line,) = ax.plot(rec["shear_disp_mm"][idx], rec[y][idx], style, color=colour, lw=lw)
            if c == ncyc[s]:
                handles[label] = line
    law = dmeta.get("joint_model") or dmeta.get("law") or os.path.splitext(os.path.basename(a.model))[0]
    specimen = mmeta.get("specimen") or os.path.splitext(os.path.basename(a.measured))[0]
    source = mmeta.get("source", "")
    title = a.title or f"{specimen}: measurement{' (' + source + ')' if source else ''} and model ({law})"
    fig.suptitle(title)
    axes[0].set_ylabel("shear stress [MPa]")
    axes[1].set_ylabel("normal displacement [mm] (dilation +)")
    for ax in axes:
        ax.set_xlabel("shear displacement [mm]")
        ax.axhline(0.0, color="0.7", lw=0.6)
        ax.axvline(0.0, color="0.7", lw=0.6)
        ax.grid(True, lw=0.3, alpha=0.5)
    axes[0].legend(handles.values(), handles.keys(), fontsize=8, loc="best")
    note = "solid: measured, dashed: model" + ("; darker shades: later cycles" if any(
        c > 1 for _, c, _ in pieces(meas)) else "")
    axes[1].set_title(note, fontsize=9)
    fig.savefig(a.out, dpi=110)


if __name__ == "__main__":
    main()
