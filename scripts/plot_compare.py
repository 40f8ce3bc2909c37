#!/usr/bin/python3
"""Model against measurement for one direct-shear test, like the CNWRA report's Figures 5-1..5-44.

  plot_compare.py MEASURED.csv MODEL.csv -o FIGURE.png [--title TEXT]

Two panels: shear stress [MPa] and normal displacement [mm], both against shear displacement
[mm]; the measurement in solid lines, the model dashed, one colour per stage (shades of it for
successive cycles, darker = later). Both files are in the measurement format
(docs/measurement-format.md). Run with Debian's /usr/bin/python3 (python3-matplotlib);
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


def reversals(u, h):
    """Turning rows by hysteresis h and the first stroke's direction (as find_reversals in
    framework/analysis/segmentation.cpp)."""
    turns, d, first, ext, imin, imax = [], 0, 0, 0, 0, 0
    for i in range(1, len(u)):
        x = u[i]
        if d == 0:
            imax = i if x > u[imax] else imax
            imin = i if x < u[imin] else imin
            if u[imax] - x > h:
                d = first = -1
                ext = i
            elif x - u[imin] > h:
                d = first = 1
                ext = i
        elif d > 0:
            if x > u[ext]:
                ext = i
            elif u[ext] - x > h:
                turns.append(ext)
                d, ext = -1, i
        else:
            if x < u[ext]:
                ext = i
            elif x - u[ext] > h:
                turns.append(ext)
                d, ext = 1, i
    return turns, first


def cycle_starts(u):
    """Rows where cycles begin, by the rule of rockdem compare (segmentation.cpp): a new cycle
    starts when the joint moves away on the first stroke's side after having come back to the
    origin; reversals count beyond 2 % of the stage's displacement range."""
    u = [float(x) for x in u]
    h = 0.02 * (max(u) - min(u)) if u else 0.0
    turns, first = reversals(u, h)
    starts = [0]
    if first == 0:
        return starts
    s0, first_part, prev_reached = 0, True, False
    for k in range(len(turns) + 1):
        cb = 0 if k == 0 else turns[k - 1]
        b = 0 if k == 0 else turns[k - 1] + 1
        e = turns[k] + 1 if k < len(turns) else len(u)
        m = first if k % 2 == 0 else -first
        start_side = (1 if u[cb] > 0 else -1) if abs(u[cb]) > h else m
        if start_side == m:
            parts = [(b, e, m, True, False)]
        elif m * u[e - 1] > h:
            r = b
            while r < e and m * u[r] < 0:
                r += 1
            parts = [(b, r, -m, False, True), (r, e, m, True, False)]
        else:
            parts = [(b, e, -m, False, abs(u[e - 1]) <= h)]
        for pb, pe, side, away, reached in parts:
            if pb == pe:
                prev_reached = prev_reached or reached
                continue
            s0 = s0 or side
            if away and side == s0 and not first_part and prev_reached:
                starts.append(pb)
            prev_reached = not away and reached
            first_part = False
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
