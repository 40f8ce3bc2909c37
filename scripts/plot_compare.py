#!/usr/bin/python3
"""Model against measurement for one direct-shear test, like the CNWRA report's Figures 5-1..5-44.

  plot_compare.py MEASURED.csv MODEL.csv -o FIGURE.png [--title TEXT]

Shear stress [MPa] above normal displacement [mm] on a shared shear-displacement axis [mm], as
rock-joint papers draw a direct-shear test: the measurement in black, the model in a colour per
stage; solid while the joint moves away from the mated position (quadrants 1 and 3), dotted while
it returns (4 and 2), arrows along the first cycle for the direction of shearing. Cyclic tests
draw cycles 1, 2, 5, 10, 20, 50, ... and the last (numbered), the others faint, and add a column
of peak and end-of-stroke strength and of dilation against cycle number. Both files are in the measurement format
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
from matplotlib.lines import Line2D  # noqa: E402

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


def moving_away(rec):
    """Per row: True where the joint moves away from the mated position (quadrants 1 and 3),
    False where it returns (4 and 2), by each stroke's direction between reversals (as rockdem
    compare numbers quadrants), not by the sign of a noisy row-to-row difference."""
    u = rec["shear_disp_mm"]
    away = np.zeros(len(u), dtype=bool)
    stage = rec["stage"].astype(int)
    for s in np.unique(stage):
        idx = np.nonzero(stage == s)[0]
        us = u[idx]
        h = 0.02 * (us.max() - us.min()) if len(us) else 0.0
        turns, first = reversals(list(map(float, us)), h)
        if first == 0:
            away[idx] = True
            continue
        bounds = [0] + [t + 1 for t in turns] + [len(us)]
        for k in range(len(bounds) - 1):
            d = first if k % 2 == 0 else -first
            seg = slice(bounds[k], bounds[k + 1])
            away[idx[seg]] = np.sign(us[seg]) == d
    return away


def selected_cycles(n):
    """The cycles a paper labels: 1, 2, 5, 10, 20, 50, ... and the last."""
    picks, k = [], 1
    while k <= n:
        for m in (1, 2, 5):
            if m * k <= n:
                picks.append(m * k)
        k *= 10
    return sorted(set(picks) | {n})


def branches(x, y, away):
    """Runs of rows on the same kind of branch, each with its boundary row so lines join."""
    out, b = [], 0
    for i in range(1, len(x) + 1):
        if i == len(x) or away[i] != away[b]:
            e = min(i + 1, len(x))
            out.append((x[b:e], y[b:e], bool(away[b])))
            b = i
    return out


def cycle_metrics(rec, parts):
    """Per (stage, cycle): peak strength (largest |shear stress| while moving away), end-of-stroke
    strength (|shear stress| at the cycle's largest |displacement| on each side, averaged), peak
    dilation and normal displacement at the end of the cycle."""
    out = {}
    away = moving_away(rec)
    u, tau, v = rec["shear_disp_mm"], rec["shear_stress_MPa"], rec["normal_disp_mm"]
    for s, c, idx in parts:
        a = idx[away[idx]]
        peak = np.max(np.abs(tau[a])) if len(a) else np.nan
        ends = []
        for side in (1, -1):
            on = idx[side * u[idx] > 0]
            if len(on):
                ends.append(abs(tau[on[np.argmax(side * u[on])]]))
        out[(s, c)] = (peak, np.mean(ends) if ends else np.nan, np.max(v[idx]), v[idx[-1]])
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

    stages = sorted(set(meas["stage"].astype(int)) | set(model["stage"].astype(int)))
    mparts, dparts = pieces(meas), pieces(model)
    ncyc = {}
    for s, c, _ in mparts + dparts:
        ncyc[s] = max(ncyc.get(s, 0), c)
    cyclic = any(n > 1 for n in ncyc.values())

    # Shear stress above normal displacement on one shear-displacement axis, as rock-joint papers
    # draw a direct-shear test; for cyclic tests a column of strength and dilation per cycle.
    fig = plt.figure(figsize=(13.5 if cyclic else 8.5, 9), constrained_layout=True)
    gs = fig.add_gridspec(2, 2 if cyclic else 1, width_ratios=[2, 1] if cyclic else [1])
    ax_t = fig.add_subplot(gs[0, 0])
    ax_v = fig.add_subplot(gs[1, 0], sharex=ax_t)
    colours = plt.rcParams["axes.prop_cycle"].by_key()["color"]
    stage_colour = {s: colours[i % len(colours)] for i, s in enumerate(stages)}

    def sigma_n(s):
        rows = meas["stage"] == s
        return np.median(meas["normal_stress_MPa"][rows]) if np.any(rows) else np.nan

    for rec, parts, who in ((meas, mparts, "measured"), (model, dparts, "model")):
        away = moving_away(rec)
        for s, c, idx in parts:
            picked = c in selected_cycles(ncyc[s])
            colour = "black" if who == "measured" else stage_colour[s]
            lw = (1.3 if who == "measured" else 1.5) if picked else 0.5
            alpha = 1.0 if picked else 0.18
            for ax, y in ((ax_t, "shear_stress_MPa"), (ax_v, "normal_disp_mm")):
                for bx, by, is_away in branches(rec["shear_disp_mm"][idx], rec[y][idx], away[idx]):
                    ax.plot(bx, by, "-" if is_away else ":", color=colour, lw=lw, alpha=alpha)
            if who == "measured" and picked and ncyc[s] > 1:
                # The cycle's number where it reaches its largest positive displacement.
                u = rec["shear_disp_mm"][idx]
                k = idx[np.argmax(u)]
                ax_t.annotate(str(c), (rec["shear_disp_mm"][k], rec["shear_stress_MPa"][k]), fontsize=7,
                              xytext=(3, 3), textcoords="offset points", color="0.25")
    # Arrows along the first measured cycle of the first stage: the direction of shearing.
    for s, c, idx in mparts[:1]:
        u, t = meas["shear_disp_mm"][idx], meas["shear_stress_MPa"][idx]
        h = 0.02 * (u.max() - u.min()) if len(u) else 0.0
        turns, _ = reversals(list(map(float, u)), h)
        bounds = [0] + [x + 1 for x in turns] + [len(u)]
        for k in range(len(bounds) - 1):
            b, e = bounds[k], bounds[k + 1]
            if e - b < 6:
                continue
            i0, i1 = b + int(0.45 * (e - b)), b + int(0.55 * (e - b))
            ax_t.annotate("", xy=(u[i1], t[i1]), xytext=(u[i0], t[i0]),
                          arrowprops=dict(arrowstyle="-|>", color="black", lw=1.0, mutation_scale=14))

    law = dmeta.get("joint_model") or dmeta.get("law") or os.path.splitext(os.path.basename(a.model))[0]
    specimen = mmeta.get("specimen") or os.path.splitext(os.path.basename(a.measured))[0]
    source = mmeta.get("source", "")
    title = a.title or f"{specimen}: measurement{' (' + source + ')' if source else ''} and model ({law})"
    fig.suptitle(title, wrap=True)
    ax_t.set_ylabel("shear stress [MPa]")
    ax_v.set_ylabel("normal displacement [mm] (dilation +)")
    ax_v.set_xlabel("shear displacement [mm]")
    plt.setp(ax_t.get_xticklabels(), visible=False)
    for ax in (ax_t, ax_v):
        ax.axhline(0.0, color="0.7", lw=0.6)
        ax.axvline(0.0, color="0.7", lw=0.6)
        ax.grid(True, lw=0.3, alpha=0.5)
    handles = [Line2D([], [], color="black", lw=1.3, label="measured")]
    for s in stages:
        sn = sigma_n(s)
        handles.append(Line2D([], [], color=stage_colour[s], lw=1.5,
                              label=f"model, stage {s}" + (f" ({sn:.3g} MPa)" if np.isfinite(sn) else "")))
    handles += [Line2D([], [], color="0.3", ls="-", label="moving away from the origin (quadrants 1, 3)"),
                Line2D([], [], color="0.3", ls=":", label="returning toward it (quadrants 4, 2)")]
    ax_t.legend(handles=handles, fontsize=8, loc="best")
    if cyclic:
        cyc = ", ".join(f"stage {s}: {', '.join(map(str, selected_cycles(n)))}" for s, n in sorted(ncyc.items()) if n > 1)
        ax_v.set_title(f"cycles drawn (numbered above): {cyc}; the others faint", fontsize=8, wrap=True)

        ax_p = fig.add_subplot(gs[0, 1])
        ax_d = fig.add_subplot(gs[1, 1], sharex=ax_p)
        markers = "os^Dv<>"
        for rec, parts, who in ((meas, mparts, "measured"), (model, dparts, "model")):
            m = cycle_metrics(rec, parts)
            for i, s in enumerate(stages):
                cs = sorted(c for (ss, c) in m if ss == s)
                if not cs:
                    continue
                colour = "black" if who == "measured" else stage_colour[s]
                mk, ls = markers[i % len(markers)], "-" if who == "measured" else "--"
                vals = np.array([m[(s, c)] for c in cs])
                ax_p.plot(cs, vals[:, 0], ls, marker=mk, color=colour, ms=4, lw=0.9)
                ax_p.plot(cs, vals[:, 1], ls, marker=mk, color=colour, ms=4, lw=0.6, mfc="white")
                ax_d.plot(cs, vals[:, 2], ls, marker=mk, color=colour, ms=4, lw=0.9)
                ax_d.plot(cs, vals[:, 3], ls, marker=mk, color=colour, ms=4, lw=0.6, mfc="white")
        ax_p.set_ylabel("shear strength [MPa]")
        ax_p.set_title("filled: peak while moving away; open: at the end of the strokes", fontsize=8, wrap=True)
        ax_d.set_ylabel("normal displacement [mm]")
        ax_d.set_title("filled: largest in the cycle; open: at its end", fontsize=8)
        ax_d.set_xlabel("cycle number")
        plt.setp(ax_p.get_xticklabels(), visible=False)
        for ax in (ax_p, ax_d):
            ax.grid(True, lw=0.3, alpha=0.5)
            ax.xaxis.get_major_locator().set_params(integer=True)
        ax_p.legend(handles=[Line2D([], [], color="black", marker="o", label="measured (solid)"),
                             Line2D([], [], color=colours[0], marker="o", ls="--", label="model (dashed, stage colours)")],
                    fontsize=8, loc="best")
    fig.savefig(a.out, dpi=110)


if __name__ == "__main__":
    main()
