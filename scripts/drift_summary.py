#!/usr/bin/python3
"""The drift-study results of one run (<out>/drift/events.csv, docs/drift-study.md) as a short
table, stage by stage: text for a terminal, or an HTML table (--html).

Usage: /usr/bin/python3 scripts/drift_summary.py RUN_DIR [--html]
Standard library only, so that it runs wherever the run did; its readers of the drift files
(read_drift_csv, num) serve scripts/plot_drift_compare.py too.
"""
import csv
import html
import math
import os
import sys


def read_drift_csv(path):
    """The rows of a drift/*.csv file (events, contacts, fallen blocks), its # lines skipped."""
    with open(path) as f:
        return list(csv.DictReader(line for line in f if not line.startswith("#")))


def num(r, k):
    """Column k of row r as a number; NaN where it is missing or not a number."""
    try:
        return float(r[k])
    except (KeyError, ValueError):
        return math.nan


def mm(v):
    return "-" if math.isnan(v) else f"{v * 1e3:.1f}"


def main(argv):
    if len(argv) < 2 or argv[1] in ("-h", "--help"):
        print(__doc__.strip())
        return 0 if len(argv) >= 2 else 2
    run = argv[1]
    path = os.path.join(run, "drift", "events.csv")
    if not os.path.isfile(path):
        print(f"drift_summary.py: no {path}: the case needs a [drift] table (docs/drift-study.md)", file=sys.stderr)
        return 2
    head = ["stage", "kind", "largest slip near the drift [mm]", "fallen blocks (area m2)",
            "k_xx, k_yy x reference", "convergence vertical / horizontal [mm]", "loosened zone [m]"]
    table = []
    for r in read_drift_csv(path):
        fallen = int(num(r, "fallen_blocks")) if not math.isnan(num(r, "fallen_blocks")) else 0
        table.append([
            r["name"], r["kind"], mm(num(r, "max_slip_near_m")),
            f"{fallen} ({num(r, 'fallen_area_m2'):.2f})" if fallen else "0",
            f"{num(r, 'k_xx_ratio'):.2f}, {num(r, 'k_yy_ratio'):.2f}",
            f"{mm(num(r, 'vertical_convergence_m'))} / {mm(num(r, 'horizontal_convergence_m'))}",
            f"{num(r, 'loosened_extent_m'):.2f}",
        ])
    if "--html" in argv[2:]:
        print('<table border="1" cellpadding="4" style="border-collapse:collapse">')
        print("<tr>" + "".join(f"<th>{html.escape(h)}</th>" for h in head) + "</tr>")
        for t in table:
            print("<tr>" + "".join(f"<td>{html.escape(c)}</td>" for c in t) + "</tr>")
        print("</table>")
        return 0
    short = ["stage", "kind", "slip near [mm]", "fallen (m2)", "k_xx, k_yy", "conv. v / h [mm]", "loosened [m]"]
    widths = [max(len(s), *(len(t[i]) for t in table)) for i, s in enumerate(short)]
    print("  ".join(s.ljust(w) for s, w in zip(short, widths)))
    for t in table:
        print("  ".join(c.ljust(w) for c, w in zip(t, widths)))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
