#!/usr/bin/python3
"""The drift comparison over earthquake levels and records (scripts/drift-compare --pgv, --motions):
for each joint model, how slip near the drift, falls, permeability and the loosened zone grow with
the peak ground velocity of the events, record by record (docs/drift-study.md).

    /usr/bin/python3 scripts/drift_levels.py OUT VARIANT [VARIANT ...] -- POINT [POINT ...]

Each POINT is a folder OUT/<POINT> holding one comparison (scripts/plot_drift_compare.py's
summary.csv, and a run per VARIANT). What its events played is read from the runs' own results,
the `# events:` line of <run>/drift/events.csv, not from the folder's name. Writes OUT/levels.csv
(every run's rows with its record and level), OUT/figures/levels_*.png and OUT/index.html. Exit 1
when no point has results.
"""
import csv
import html
import math
import os
import re
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from drift_ensemble import SPREAD, number, split_args, status_of  # noqa: E402  (the ensemble's measures, helpers)
from plot_drift_compare import COLORS, label  # noqa: E402  (the comparison's names and colours)

# The ensemble's measures and how many contacts near the drift loosened: the largest slip can stay
# on one joint that has slipped as far as it can while the rock around it loosens further.
MEASURES = SPREAD + [("loosened_contacts", "loosened contacts", 1.0, "")]

KEEP = ["max_slip_near_m", "fallen_blocks", "fallen_area_m2", "k_xx_ratio", "k_yy_ratio", "loosened_extent_m", "loosened_contacts",
        "vertical_convergence_m", "horizontal_convergence_m", "max_speed_m_s"]  # of summary.csv
EVENT = re.compile(r"\s*([^:;]+):((?:\s+\S+ at PGV \S+ m/s)+)")
PLAYED = re.compile(r"(\S+) at PGV (\S+) m/s")


def events_played(run):
    """{event stage: [(motion, pgv m/s), ...]} from the run's drift/events.csv; {} without it."""
    try:
        with open(os.path.join(run, "drift", "events.csv")) as f:
            line = next((x for x in f if x.startswith("# events:")), "")
    except OSError:
        return {}
    out = {}
    for part in line[len("# events:"):].strip().split(";"):
        m = EVENT.match(part)
        if m:
            out[m.group(1).strip()] = [(a, float(b)) for a, b in PLAYED.findall(m.group(2))]
    return out


def describe(played):
    """(record, pgv) of a run: the one record and level all its events played, else a joined
    description and NaN (a series point whose events differ has no single level). An event's
    level is its first motion's (rockdem run --pgv scales the first; a second, vertical one keeps
    its ratio to it)."""
    records = sorted({m for v in played.values() for m, _ in v})
    levels = sorted({round(v[0][1], 6) for v in played.values() if v})
    return "+".join(records) or "?", levels[0] if len(levels) == 1 else math.nan


def main():
    args = split_args(sys.argv[1:], __doc__)
    if args is None:
        return 2
    out, variants, points = args
    runs = []  # (point, record, pgv, variant, status, why, rows)
    for p in points:
        folder = os.path.join(out, p)
        rows = {v: [] for v in variants}
        try:
            with open(os.path.join(folder, "summary.csv")) as f:
                for r in csv.DictReader(f):
                    if r["variant"] in rows:
                        rows[r["variant"]].append(r)
        except OSError:
            pass
        for v in variants:
            st, why = status_of(os.path.join(folder, v), os.path.join(folder, "logs", v + ".log"))
            record, pgv = describe(events_played(os.path.join(folder, v)))
            runs.append((p, record, pgv, v, st, why, rows[v]))
    if not any(r[6] for r in runs):
        print(f"drift_levels: no point of the series in {out} has results (<point>/summary.csv)", file=sys.stderr)
        return 1

    with open(os.path.join(out, "levels.csv"), "w", newline="") as f:
        w = csv.writer(f, lineterminator="\n")
        w.writerow(["record", "pgv_m_s", "point", "variant", "status", "stage", "name", "kind"] + KEEP)
        for p, record, pgv, v, st, _, rows in runs:
            for r in rows:
                w.writerow([record, "" if math.isnan(pgv) else f"{pgv:g}", p, v, st, r["stage"], r["name"], r["kind"]] +
                           [r.get(k, "") for k in KEEP])

    # The records with results (a run that stopped before its drift results has no known record).
    records = sorted({r[1] for r in runs if r[6]})
    def after_first_event(rows):
        return next((r for r in rows if r["kind"] == "event"), None)

    figs = os.path.join(out, "figures")
    os.makedirs(figs, exist_ok=True)
    for key, title, scale, unit in MEASURES:
        fig, axes = plt.subplots(1, len(records), figsize=(4.2 * len(records) + 1.5, 3.6), squeeze=False)
        for ax, rec in zip(axes[0], records):
            for j, v in enumerate(variants):
                pts = sorted(((pgv, rows) for _, record, pgv, var, _, _, rows in runs
                              if record == rec and var == v and rows and not math.isnan(pgv)), key=lambda t: t[0])
                if not pts:
                    continue
                c = COLORS[j % len(COLORS)]
                ax.plot([x for x, _ in pts], [number(rows[-1][key]) * scale for _, rows in pts], "o-", color=c,
                        label=f"{label(v)}, after {pts[0][1][-1]['name']}")
                e1 = [(x, after_first_event(rows)) for x, rows in pts]
                e1 = [(x, r) for x, r in e1 if r is not None]
                if e1:
                    ax.plot([x for x, _ in e1], [number(r[key]) * scale for _, r in e1], "o--", mfc="none", color=c,
                            alpha=0.7, label=f"{label(v)}, after {e1[0][1]['name']}")
            ax.set_xlabel("peak ground velocity of every event [m/s]")
            ax.set_ylabel(f"{title}{' [' + unit + ']' if unit else ''}")
            ax.set_title(rec, fontsize=9)
            ax.grid(alpha=0.3)
        handles, labels = axes[0][0].get_legend_handles_labels()
        fig.legend(handles, labels, fontsize=7, loc="lower center", ncol=2, bbox_to_anchor=(0.5, 1.0))
        fig.tight_layout()
        fig.savefig(os.path.join(figs, f"levels_{key}.png"), dpi=110, bbox_inches="tight")
        plt.close(fig)

    e = html.escape
    page = ["<!doctype html><meta charset='utf-8'><title>Drift comparison over earthquake levels and records</title>",
            "<style>body{font-family:sans-serif;max-width:1200px;margin:auto} table{border-collapse:collapse;font-size:90%}"
            " td,th{border:1px solid #bbb;padding:2px 6px} .bad{color:#b00}</style>",
            "<h1>Drift comparison over earthquake levels and records</h1>",
            "<p>Each point of the series is a comparison of its own (the same case, every event at the level and "
            "with the record named): " + ", ".join(f"<a href='{e(p)}/index.html'>{e(p)}</a>" for p in points) +
            ". What each run's events played is read from its <code>drift/events.csv</code>.</p>"]
    bad = [r for r in runs if r[4] != "finished"]
    if bad:
        page.append("<h2 class='bad'>Runs that did not finish</h2><ul>")
        for p, _, _, v, st, why, rows in bad:
            reached = rows[-1]["name"] if rows else "none from the excavation on"
            page.append(f"<li class='bad'>{e(label(v))}, {e(p)}: {e(st)} (last stage with results: {e(reached)})"
                        f"{': ' + e(why[:300]) if why else ''}</li>")
        page.append("</ul>")
    page.append("<h2>After the first event and after the last stage</h2><table><tr><th>record</th><th>PGV [m/s]</th>"
                "<th>model</th><th>fallen blocks (area m²)</th>" +
                "".join(f"<th>{e(t)}{' [' + u + ']' if u else ''}<br>event 1 → last</th>" for k, t, _, u in MEASURES
                        if k != "fallen_area_m2") + "</tr>")
    for p, record, pgv, v, st, _, rows in sorted(runs, key=lambda r: (r[1], r[2], variants.index(r[3]))):
        if not rows:
            page.append(f"<tr><td>{e(record)}</td><td>{pgv:g}</td><td>{e(label(v))}</td><td colspan=6 class='bad'>"
                        f"no results ({e(st)})</td></tr>")
            continue
        first, last = after_first_event(rows) or rows[0], rows[-1]
        cells = [f"{number(last['fallen_blocks']):.0f} ({number(last['fallen_area_m2']):.3g})"]
        for k, _, sc, _ in MEASURES:
            if k != "fallen_area_m2":
                cells.append(f"{number(first[k]) * sc:.3g} → {number(last[k]) * sc:.3g}")
        page.append(f"<tr><td>{e(record)}</td><td>{pgv:g}</td><td>{e(label(v))}</td>" +
                    "".join(f"<td>{e(c)}</td>" for c in cells) + "</tr>")
    page.append("</table>")
    for key, *_ in MEASURES:
        page.append(f"<p><img src='figures/levels_{key}.png'></p>")
    page.append("<p>Files: <a href='levels.csv'>levels.csv</a> (every run's rows, with its record and level).</p>")
    with open(os.path.join(out, "index.html"), "w") as f:
        f.write("\n".join(page))
    print(f"drift_levels: {os.path.join(out, 'index.html')}: {len(variants)} models x {len(points)} points "
          f"({', '.join(records)})")
    return 0


if __name__ == "__main__":
    sys.exit(main())
