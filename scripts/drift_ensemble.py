#!/usr/bin/python3
"""The drift comparison over several realisations of the rock mass (scripts/drift-compare --seeds):
for each joint model and stage, in how many realisations blocks had fallen at the stage's end, and
the spread of slip near the drift, permeability and the loosened zone (docs/drift-study.md).

    /usr/bin/python3 scripts/drift_ensemble.py OUT VARIANT [VARIANT ...] -- SEED [SEED ...]

Reads OUT/seed<SEED>/summary.csv and each run's manifest (OUT/seed<SEED>/<VARIANT>/manifest.json),
as scripts/plot_drift_compare.py wrote them for each seed, and the blocks each run's scale_off took
out (OUT/seed<SEED>/<VARIANT>/scaled_off.csv). Writes OUT/ensemble.csv (one row per model and
stage), OUT/realisations.csv (every run's rows with its seed), OUT/scaled_off.csv (every block
scaled off, with its seed and model), OUT/figures/ensemble_*.png and OUT/index.html. Exit 1 when
no realisation has results.
"""
import csv
import html
import json
import math
import os
import statistics
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from plot_drift_compare import COLORS, label  # noqa: E402  (the comparison's names and colours)

SPREAD = [("max_slip_near_m", "largest slip near the drift", 1e3, "mm"),
          ("k_xx_ratio", "k_xx / reference", 1.0, ""),
          ("k_yy_ratio", "k_yy / reference", 1.0, ""),
          ("loosened_extent_m", "loosened zone", 1.0, "m"),
          ("fallen_area_m2", "fallen area", 1.0, "m²")]


def number(text):
    try:
        return float(text)
    except (TypeError, ValueError):
        return math.nan


def status_of(run, log):
    """The run's manifest status ("finished", "unstable", ...) and the first line of its log that
    says why it stopped, if any."""
    try:
        with open(os.path.join(run, "manifest.json")) as f:
            st = json.load(f).get("status", "?")
    except (OSError, ValueError):
        st = "no manifest"
    why = ""
    try:
        with open(log) as f:
            why = next((line.strip() for line in f if line.startswith("rockdem:") and
                        ("unstable" in line or "error" in line)), "")
    except OSError:
        pass
    return st, why


def scaled_off(run):
    """The blocks a run's scale_off took out (rows of its scaled_off.csv); None when it wrote none."""
    try:
        with open(os.path.join(run, "scaled_off.csv")) as f:
            return list(csv.DictReader(line for line in f if not line.startswith("#")))
    except OSError:
        return None


def spread(values, scale):
    v = sorted(x * scale for x in values if not math.isnan(x))
    if not v:
        return ""
    if len(v) == 1:
        return f"{v[0]:.3g}"
    return f"{statistics.median(v):.3g} ({v[0]:.3g} to {v[-1]:.3g})"


def split_args(argv, doc):
    """OUT VARIANT [VARIANT ...] -- ITEM [ITEM ...] as (out, variants, items); None, with the
    script's usage printed, when they are not so (drift_ensemble.py and drift_levels.py)."""
    if "--" not in argv or argv.index("--") < 2 or argv.index("--") == len(argv) - 1:
        print(doc, file=sys.stderr)
        return None
    cut = argv.index("--")
    return argv[0], argv[1:cut], argv[cut + 1:]


def main():
    args = split_args(sys.argv[1:], __doc__)
    if args is None:
        return 2
    out, variants, seeds = args
    # rows[v][seed] = that run's summary rows (the stages it reached, from the excavation on)
    rows = {v: {} for v in variants}
    status = {v: {} for v in variants}
    for s in seeds:
        folder = os.path.join(out, f"seed{s}")
        for v in variants:
            status[v][s] = status_of(os.path.join(folder, v), os.path.join(folder, "logs", v + ".log"))
            rows[v][s] = []
        try:
            with open(os.path.join(folder, "summary.csv")) as f:
                for r in csv.DictReader(f):
                    if r["variant"] in rows:
                        rows[r["variant"]][s].append(r)
        except OSError:
            pass
    scaled = {(v, s): scaled_off(os.path.join(out, f"seed{s}", v)) for v in variants for s in seeds}
    with open(os.path.join(out, "scaled_off.csv"), "w", newline="") as f:
        w = csv.writer(f, lineterminator="\n")
        w.writerow(["seed", "variant", "stage_name", "step", "block", "moved_m", "area_m2"])
        for s in seeds:
            for v in variants:
                for r in scaled[(v, s)] or []:
                    w.writerow([s, v, r["stage_name"], r["step"], r["block"], r["moved_m"], r["area_m2"]])
    if not any(rows[v][s] for v in variants for s in seeds):
        print(f"drift_ensemble: no realisation in {out} has results (seed<N>/summary.csv)", file=sys.stderr)
        return 1
    # The stages, in order, as the runs that went furthest have them.
    stages = {}
    for v in variants:
        for s in seeds:
            for r in rows[v][s]:
                stages.setdefault(int(r["stage"]), (r["name"], r["kind"]))
    order = sorted(stages)

    with open(os.path.join(out, "realisations.csv"), "w", newline="") as f:
        w = None
        for s in seeds:
            for v in variants:
                for r in rows[v][s]:
                    if w is None:
                        w = csv.writer(f, lineterminator="\n")
                        w.writerow(["seed"] + list(r.keys()))
                    w.writerow([s] + list(r.values()))

    table = []  # (variant, stage, name, kind, reached, fallen, spreads...)
    for v in variants:
        for k in order:
            at = [next((r for r in rows[v][s] if int(r["stage"]) == k), None) for s in seeds]
            at = [r for r in at if r is not None]
            fallen = sum(1 for r in at if number(r["fallen_blocks"]) > 0)
            table.append([v, k, stages[k][0], stages[k][1], len(at), fallen] +
                         [spread([number(r[c]) for r in at], sc) for c, _, sc, _ in SPREAD])
    with open(os.path.join(out, "ensemble.csv"), "w", newline="") as f:
        w = csv.writer(f, lineterminator="\n")
        w.writerow(["variant", "stage", "name", "kind", "realisations", "with_fallen_blocks"] +
                   [f"{c} median (range)" for c, _, _, _ in SPREAD])
        w.writerows(table)

    figs = os.path.join(out, "figures")
    os.makedirs(figs, exist_ok=True)
    # Share of realisations with fallen blocks, stage by stage, one line per model.
    # Each point says how many of how many (a share of 1 of 1 is no evidence); the models are set
    # slightly apart so that equal shares stay visible.
    fig, ax = plt.subplots(figsize=(8, 4))
    for j, v in enumerate(variants):
        xs, ys, counts = [], [], []
        for t in table:
            if t[0] == v and t[4] > 0:
                xs.append(order.index(t[1]) + 0.06 * (j - (len(variants) - 1) / 2))
                ys.append(t[5] / t[4])
                counts.append(f"{t[5]}/{t[4]}")
        ax.plot(xs, ys, "o-", color=COLORS[j % len(COLORS)], label=label(v))
        for x, y, c in zip(xs, ys, counts):
            ax.annotate(c, (x, y), textcoords="offset points", xytext=(3, 4 + 8 * j), fontsize=7, color=COLORS[j % len(COLORS)])
    ax.set_xticks(range(len(order)), [stages[k][0] for k in order])
    ax.set_ylim(-0.05, 1.25)
    ax.set_ylabel("realisations with fallen blocks")
    ax.set_title(f"{len(seeds)} realisations (seeds {', '.join(seeds)}): share with blocks fallen at the stage's end", fontsize=9)
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(os.path.join(figs, "ensemble_falls.png"), dpi=110)
    plt.close(fig)
    # Largest slip near the drift after each stage, every realisation a point.
    fig, ax = plt.subplots(figsize=(8, 4))
    width = 0.8 / max(1, len(variants))
    for j, v in enumerate(variants):
        named = False
        for s in seeds:
            pts = [(order.index(int(r["stage"])) + (j - (len(variants) - 1) / 2) * width, number(r["max_slip_near_m"]) * 1e3)
                   for r in rows[v][s]]
            if pts:
                ax.plot(*zip(*pts), "o", ms=4, color=COLORS[j % len(COLORS)], alpha=0.7, label=None if named else label(v))
                named = True
    ax.set_xticks(range(len(order)), [stages[k][0] for k in order])
    ax.set_ylabel("largest slip near the drift [mm]")
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(os.path.join(figs, "ensemble_slip.png"), dpi=110)
    plt.close(fig)

    e = html.escape
    page = [f"<!doctype html><meta charset='utf-8'><title>Drift comparison over {len(seeds)} realisations</title>",
            "<style>body{font-family:sans-serif;max-width:1100px;margin:auto} table{border-collapse:collapse;font-size:90%}"
            " td,th{border:1px solid #bbb;padding:2px 6px} .bad{color:#b00}</style>",
            f"<h1>Drift comparison over {len(seeds)} realisations of the joint sets</h1>",
            f"<p>Seeds {e(', '.join(seeds))}; each model's runs share them. Per realisation its own comparison: "
            + ", ".join(f"<a href='seed{e(s)}/index.html'>seed {e(s)}</a>" for s in seeds) + ".</p>"]
    unfinished = [(v, s, st) for v in variants for s in seeds for st in [status[v][s]] if st[0] != "finished"]
    if unfinished:
        page.append("<h2 class='bad'>Runs that did not finish</h2><ul>")
        for v, s, (st, err) in unfinished:
            reached = rows[v][s][-1]["name"] if rows[v][s] else "none from the excavation on"
            page.append(f"<li class='bad'>{e(label(v))}, seed {e(s)}: {e(st)} (last stage with results: {e(reached)})"
                        f"{': ' + e(err[:300]) if err else ''}</li>")
        page.append("</ul><p>A realisation counts in a stage only where its run reached that stage's end.</p>")
    page.append("<h2>By model and stage</h2><table><tr><th>model</th><th>stage</th><th>realisations</th>"
                "<th>with fallen blocks</th>" + "".join(f"<th>{e(t)}{' [' + u + ']' if u else ''}<br>median (range)</th>"
                                                         for _, t, _, u in SPREAD) + "</tr>")
    for t in table:
        page.append(f"<tr><td>{e(label(t[0]))}</td><td>{e(t[2])}</td><td>{t[4]}</td><td>{t[5]} of {t[4]}</td>"
                    + "".join(f"<td>{e(x)}</td>" for x in t[6:]) + "</tr>")
    page.append("</table>")
    page.append("<p><img src='figures/ensemble_falls.png'></p><p><img src='figures/ensemble_slip.png'></p>")
    if any(x is not None for x in scaled.values()):
        # What each realisation lost before the reference state (a stage's scale_off): the drift's
        # overbreak, which the results are measured after.
        page.append("<h2>Blocks scaled off (overbreak)</h2><p>Taken out by a stage's <code>scale_off</code> "
                    "before the reference state; the results above are measured after it.</p>"
                    "<table><tr><th>seed</th>" + "".join(f"<th>{e(label(v))}</th>" for v in variants) + "</tr>")
        for s in seeds:
            cells = []
            for v in variants:
                r = scaled[(v, s)]
                if r is None:
                    cells.append("<td>(no record)</td>")
                elif not r:
                    cells.append("<td>none</td>")
                else:
                    area = sum(number(x["area_m2"]) for x in r)
                    cells.append(f"<td>{e(', '.join(x['block'] for x in r))} ({area:.3g} m²)</td>")
            page.append(f"<tr><td>{e(s)}</td>" + "".join(cells) + "</tr>")
        page.append("</table>")
    page.append("<p>Files: <a href='ensemble.csv'>ensemble.csv</a> (this table), "
                "<a href='realisations.csv'>realisations.csv</a> (every run's rows, with its seed), "
                "<a href='scaled_off.csv'>scaled_off.csv</a> (every block scaled off, with its seed and model).</p>")
    with open(os.path.join(out, "index.html"), "w") as f:
        f.write("\n".join(page))
    print(f"drift_ensemble: {os.path.join(out, 'index.html')}: {len(variants)} models x {len(seeds)} realisations")
    return 0


if __name__ == "__main__":
    sys.exit(main())
