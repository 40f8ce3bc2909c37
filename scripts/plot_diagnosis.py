#!/usr/bin/python3
"""Figures of `rockdem diagnose --report DIR` (run by Debian's /usr/bin/python3 with matplotlib).

usage: plot_diagnosis.py DIR/diagnosis.json --out DIR

Reads the diagnosis JSON and DIR/aligned.csv (per measured row: stage, cycle, quadrant, shear
displacement, the measurement, and each ladder step's model aligned on it) and writes:
  ladder_overlay.png   shear stress above normal displacement on one shear-displacement axis:
                       the measurement (black) with the model of each ladder step overlaid;
  residual_quadrants.png  residual (model - measured, shear stress in magnitude) by quadrant
                       (named: moving away / returning, + / - side) for the baseline and the
                       last ladder step, per variable, with units (box plots);
  error_ladder.png     combined / per-variable NRMSE at each step, and the change in the
                       information criterion (IC, with the effective number of independent
                       residuals) each added effect made;
  covariates.png       covariate scores (adjusted eta^2) of the baseline residual, each stage's mean removed.
"""
import argparse
import csv
import json
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


# The report's quadrant numbers, spelled out (docs/user-guide-compare.md, "quadrant").
QUADRANT_NAMES = {1: "Q1: moving away\non the + side", 4: "Q4: returning\nfrom the + side",
                  3: "Q3: moving away\non the - side", 2: "Q2: returning\nfrom the - side"}


def read_aligned(path):
    with open(path, newline="") as f:
        rows = list(csv.reader(f))
    head, body = rows[0], rows[1:]
    cols = {name: [float(r[i]) for r in body] for i, name in enumerate(head)}
    return cols


def step_name(base, effects):
    return base + "".join(" + " + e for e in effects)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("json")
    ap.add_argument("--out", required=True)
    a = ap.parse_args()
    with open(a.json) as f:
        d = json.load(f)
    cols = read_aligned(os.path.join(os.path.dirname(a.json), "aligned.csv"))
    os.makedirs(a.out, exist_ok=True)
    ladder = d["ladder"]
    base = d["base_law"]
    u = cols["shear_disp_mm"]
    quad = [int(q) for q in cols["quadrant"]]
    colours = plt.rcParams["axes.prop_cycle"].by_key()["color"]

    # 1. Measurement with each ladder step's model: shear stress above normal displacement on one
    #    shear-displacement axis, the measurement in black, each step in a colour.
    fig, ax = plt.subplots(2, 1, figsize=(9, 8.5), sharex=True)
    for j, (var, label) in enumerate([("shear_stress", "shear stress [MPa]"),
                                      ("normal_disp", "normal displacement [mm] (dilation +)")]):
        meas = cols[var + ("_MPa" if var == "shear_stress" else "_mm")]
        ax[j].plot(u, meas, color="black", lw=1.2, label="measurement")
        for k, s in enumerate(ladder):
            ax[j].plot(u, cols["%s_%d" % (var, k)], lw=0.9, ls="--", color=colours[k % len(colours)],
                       label="%s (NRMSE %.3f)" % (step_name(base, s["effects"]), s["nrmse"]["combined"]))
        ax[j].set_ylabel(label)
        ax[j].axhline(0.0, color="0.7", lw=0.6)
        ax[j].axvline(0.0, color="0.7", lw=0.6)
        ax[j].grid(alpha=0.3)
    ax[1].set_xlabel("shear displacement [mm]")
    ax[0].legend(fontsize=8)
    fig.suptitle("%s: the measurement (black) and the model at each step of the ladder" % os.path.basename(d["data"]),
                 wrap=True)
    fig.tight_layout()
    fig.savefig(os.path.join(a.out, "ladder_overlay.png"), dpi=110)
    plt.close(fig)

    # 2. Residuals by quadrant, baseline and final step, with the quadrants named.
    fig, ax = plt.subplots(1, 2, figsize=(13, 5))
    last = len(ladder) - 1
    for j, (var, col, unit) in enumerate([("shear_stress", "shear_stress_MPa", "MPa"),
                                          ("normal_disp", "normal_disp_mm", "mm")]):
        meas = cols[col]
        ticks, names = [], []
        pos = 0.0
        for q in (1, 4, 3, 2):
            idx = [i for i, qq in enumerate(quad) if qq == q]
            if not idx:
                continue
            steps = sorted({0, last})
            for n, k in enumerate(steps):
                m = cols["%s_%d" % (var, k)]
                if var == "shear_stress":  # in magnitude: positive = the model is stronger
                    r = [abs(m[i]) - abs(meas[i]) for i in idx]
                else:
                    r = [m[i] - meas[i] for i in idx]
                bp = ax[j].boxplot([r], positions=[pos + n * 0.8], widths=0.6, showfliers=False, patch_artist=True)
                bp["boxes"][0].set_facecolor("0.85" if k == 0 else "tab:blue")
                bp["medians"][0].set_color("black")
            ticks.append(pos + 0.4 * (len(steps) - 1))
            names.append(QUADRANT_NAMES[q])
            pos += 2.2
        ax[j].set_xticks(ticks)
        ax[j].set_xticklabels(names)
        if j == 0:
            from matplotlib.patches import Patch
            ax[j].legend(handles=[Patch(facecolor="0.85", edgecolor="black", label="baseline"),
                                  Patch(facecolor="tab:blue", edgecolor="black", label="last ladder step")],
                         fontsize=8, loc="best")
        ax[j].axhline(0.0, color="grey", lw=0.8)
        ax[j].tick_params(axis="x", labelsize=8)
        if var == "shear_stress":
            ax[j].set_ylabel("|model| - |measured| shear stress [MPa]\n(positive: the model is stronger)")
        else:
            ax[j].set_ylabel("model - measured normal displacement [mm]\n(positive: the model dilates more)")
        ax[j].set_title(var.replace("_", " ").replace("disp", "displacement") + " residual by quadrant", fontsize=10)
        ax[j].grid(alpha=0.3, axis="y")
    fig.tight_layout()
    fig.savefig(os.path.join(a.out, "residual_quadrants.png"), dpi=110)
    plt.close(fig)

    # 3. The ladder: the error at each step and the change in the criterion each step made.
    fig, ax = plt.subplots(1, 2, figsize=(12, 4.8))
    names = ["baseline " + base] + ["+ " + s["effects"][-1] for s in ladder[1:]]
    x = list(range(len(ladder)))
    for key, mk, lab in (("combined", "o-", "combined (mean of the two)"), ("shear_stress", "s--", "shear stress"),
                         ("normal_disp", "^--", "normal displacement")):
        ax[0].plot(x, [s["nrmse"][key] for s in ladder], mk, label=lab)
    ax[0].set_ylabel("NRMSE (RMSE / measured range)")
    ax[0].set_title("the error at each step", fontsize=10)
    # The IC change the ladder decided each rung by (its decision for the effect it added).
    added = {c["step"]: c["delta_ic"] for c in d.get("ladder_decisions", []) if c["added"]}
    # (A JSON of an older rockdem has no decisions: its rungs are drawn at 0, not as BIC changes.)
    dbic = [0.0] + [added.get(k, 0.0) for k in range(1, len(ladder))]
    ax[1].bar(x[1:], dbic[1:], color=["tab:green" if v < 0 else "tab:red" for v in dbic[1:]])
    ax[1].axhline(0.0, color="black", lw=0.8)
    for k in x[1:]:
        ax[1].annotate("%+.0f" % dbic[k], (k, dbic[k]), ha="center", va="top" if dbic[k] < 0 else "bottom", fontsize=8)
    ax[1].set_ylabel("change in IC from the step before")
    ax[1].set_title("what each added effect bought (negative: kept, it explains more than it costs)", fontsize=9, wrap=True)
    ax[1].set_xlim(-0.5, len(ladder) - 0.5)
    for axx in ax:
        axx.set_xticks(x)
        axx.set_xticklabels(names, rotation=20, ha="right", fontsize=8)
        axx.grid(alpha=0.3)
    ax[0].legend(fontsize=8)
    fig.suptitle("the ladder of effects on %s" % base)
    fig.tight_layout()
    fig.savefig(os.path.join(a.out, "error_ladder.png"), dpi=110)
    plt.close(fig)

    # 4. Covariate scores.
    cov = d["covariates"]
    fig, ax = plt.subplots(figsize=(8, 4.5))
    lab = ["%s / %s" % (c["variable"].replace("_", " "), c["name"]) for c in cov]
    ax.barh(range(len(cov)), [c["score"] for c in cov], color=colours[0])
    ax.set_yticks(range(len(cov)))
    ax.set_yticklabels(lab, fontsize=8)
    ax.invert_yaxis()
    ax.set_xlabel("share of the baseline residual explained within stages (adjusted eta^2)")
    ax.grid(alpha=0.3, axis="x")
    fig.tight_layout()
    fig.savefig(os.path.join(a.out, "covariates.png"), dpi=110)
    plt.close(fig)
    return 0


if __name__ == "__main__":
    sys.exit(main())
