#!/usr/bin/python3
"""Figures of `rockdem diagnose --report DIR` (run by Debian's /usr/bin/python3 with matplotlib).

usage: plot_diagnosis.py DIR/diagnosis.json --out DIR

Reads the diagnosis JSON and DIR/aligned.csv (per measured row: stage, cycle, quadrant, shear
displacement, the measurement, and each ladder step's model aligned on it) and writes:
  ladder_overlay.png   shear stress and normal displacement against shear displacement: the
                       measurement (black) with the model of each ladder step overlaid;
  residual_quadrants.png  residual (model - measured, shear stress in magnitude) by quadrant
                       for the baseline and the last ladder step, per variable (box plots);
  error_ladder.png     combined / per-variable NRMSE and BIC falling step by step;
  covariates.png       covariate scores (adjusted eta^2) of the baseline residual.
"""
import argparse
import csv
import json
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


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

    # 1. Measurement with each ladder step's model.
    fig, ax = plt.subplots(1, 2, figsize=(13, 5))
    for j, (var, label) in enumerate([("shear_stress", "shear stress [MPa]"), ("normal_disp", "normal displacement [mm]")]):
        meas = cols[var + ("_MPa" if var == "shear_stress" else "_mm")]
        ax[j].plot(u, meas, color="black", lw=1.2, label="measurement")
        for k, s in enumerate(ladder):
            ax[j].plot(u, cols["%s_%d" % (var, k)], lw=0.9, ls="--", color=colours[k % len(colours)],
                       label="%s (NRMSE %.3f)" % (step_name(base, s["effects"]), s["nrmse"]["combined"]))
        ax[j].set_xlabel("shear displacement [mm]")
        ax[j].set_ylabel(label)
        ax[j].grid(alpha=0.3)
    ax[0].legend(fontsize=8)
    fig.suptitle("%s: measurement and the ladder of models" % os.path.basename(d["data"]))
    fig.tight_layout()
    fig.savefig(os.path.join(a.out, "ladder_overlay.png"), dpi=110)
    plt.close(fig)

    # 2. Residuals by quadrant, baseline and final step.
    fig, ax = plt.subplots(1, 2, figsize=(12, 4.5))
    last = len(ladder) - 1
    for j, (var, col) in enumerate([("shear_stress", "shear_stress_MPa"), ("normal_disp", "normal_disp_mm")]):
        meas = cols[col]
        data, labels = [], []
        for q in (1, 4, 3, 2):
            idx = [i for i, qq in enumerate(quad) if qq == q]
            if not idx:
                continue
            for k in sorted({0, last}):
                m = cols["%s_%d" % (var, k)]
                if var == "shear_stress":  # in magnitude: positive = the model is stronger
                    r = [abs(m[i]) - abs(meas[i]) for i in idx]
                else:
                    r = [m[i] - meas[i] for i in idx]
                data.append(r)
                labels.append("Q%d\n%s" % (q, "base" if k == 0 else "final"))
        if data:
            ax[j].boxplot(data, labels=labels, showfliers=False)
        ax[j].axhline(0.0, color="grey", lw=0.8)
        ax[j].set_title(var.replace("_", " ") + " residual (model - measured%s)" % (", magnitude" if j == 0 else ""))
        ax[j].grid(alpha=0.3, axis="y")
    fig.tight_layout()
    fig.savefig(os.path.join(a.out, "residual_quadrants.png"), dpi=110)
    plt.close(fig)

    # 3. The error falling step by step.
    fig, ax = plt.subplots(1, 2, figsize=(12, 4.5))
    names = ["base"] + ["+ " + s["effects"][-1] for s in ladder[1:]]
    x = list(range(len(ladder)))
    for key, mk in (("combined", "o-"), ("shear_stress", "s--"), ("normal_disp", "^--")):
        ax[0].plot(x, [s["nrmse"][key] for s in ladder], mk, label=key)
    ax[0].set_ylabel("NRMSE")
    ax[1].plot(x, [s["bic"] for s in ladder], "o-", color="black")
    ax[1].set_ylabel("BIC")
    for axx in ax:
        axx.set_xticks(x)
        axx.set_xticklabels(names, rotation=20, ha="right", fontsize=8)
        axx.grid(alpha=0.3)
    ax[0].legend()
    fig.suptitle("the error falling step by step (%s)" % base)
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
    ax.set_xlabel("share of the baseline residual explained (adjusted eta^2)")
    ax.grid(alpha=0.3, axis="x")
    fig.tight_layout()
    fig.savefig(os.path.join(a.out, "covariates.png"), dpi=110)
    plt.close(fig)
    return 0


if __name__ == "__main__":
    sys.exit(main())
