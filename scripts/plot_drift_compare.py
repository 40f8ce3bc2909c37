#!/usr/bin/python3
"""The drift comparison's report: the same drift and events run with each joint model
(scripts/drift-compare), read from each run's <run>/drift/ files (docs/drift-study.md) and shown
event by event: slip near the drift, fallen blocks, permeability, loosened zone and convergence,
with maps and histograms of the joints' slip after the last stage.

    /usr/bin/python3 scripts/plot_drift_compare.py OUT VARIANT [VARIANT ...]

Each VARIANT is a folder OUT/<variant> written by `rockdem run ... --joint`; a variant whose run
did not finish is shown up to its last stage and named at the top of the page. Writes
OUT/index.html, OUT/summary.csv and OUT/figures/*.png. Exit 1 when no variant has results.
"""
import csv
import glob
import html
import json
import math
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from drift_summary import num, read_drift_csv  # noqa: E402  (the drift files' readers)

LABELS = {
    "mohr_coulomb": "Mohr-Coulomb",
    "barton_bandis": "Barton-Bandis",
    "continuously_yielding": "Continuously-Yielding",
    "continuously_yielding_reverse_wear": "CY + reverse-shear degradation + directional wear",
    "continuously_yielding_recovery_wear": "CY + dilation recovery + directional wear",
}
COLORS = ["#1b6ca8", "#d1495b", "#2e933c", "#edae49", "#6a4c93", "#444444"]


def label(v):
    return LABELS.get(v, v)




def run_status(run):
    """The manifest's status ("finished", "unstable", ...) and the model the joints were."""
    try:
        with open(os.path.join(run, "manifest.json")) as f:
            m = json.load(f)
        return m.get("status", "?"), m.get("command_line", "")
    except (OSError, ValueError):
        return "no manifest", ""


def stage_max_speeds(run):
    """The largest of the `max_speed` history per stage number (history.h5), {} without it."""
    try:
        import h5py
        with h5py.File(os.path.join(run, "history.h5"), "r") as f:
            h = f["history"]
            if "max_speed" not in h:
                return {}
            out = {}
            for st, v in zip(h["stage"][:], h["max_speed"][:]):
                k = str(int(st))
                out[k] = max(out.get(k, 0.0), float(v))
            return out
    except (OSError, KeyError, ImportError):
        return {}


SUSPECT_SPEED = 20.0  # m/s: twice free fall through 5 m, forty times the events' PGV


def series_plot(ax, data, key, ylabel, scale=1.0, log=False):
    for i, (v, rows) in enumerate(data):
        xs = [r["name"] for r in rows]
        ys = [num(r, key) * scale for r in rows]
        ax.plot(range(len(xs)), ys, "o-", color=COLORS[i % len(COLORS)], label=label(v))
    stages = max((rows for _, rows in data), key=len)
    ax.set_xticks(range(len(stages)))
    ax.set_xticklabels([r["name"] for r in stages], rotation=30, ha="right")
    ax.set_ylabel(ylabel)
    if log:
        ax.set_yscale("log")
    ax.grid(True, alpha=0.3)


def main():
    if len(sys.argv) < 3:
        print(__doc__, file=sys.stderr)
        return 2
    out, variants = sys.argv[1], sys.argv[2:]
    figs = os.path.join(out, "figures")
    os.makedirs(figs, exist_ok=True)
    data, problems, sets = [], [], []
    for v in variants:
        run = os.path.join(out, v)
        status, _ = run_status(run)
        ev = os.path.join(run, "drift", "events.csv")
        if not os.path.exists(ev):
            problems.append(f"{label(v)}: no results ({run}/drift/events.csv missing; run status: {status})")
            continue
        rows = read_drift_csv(ev)
        if status != "finished":
            problems.append(f"{label(v)}: the run ended '{status}' after stage '{rows[-1]['name']}' "
                            f"(see {os.path.join(out, 'logs', v + '.log')}); its rows stop there")
        speeds = stage_max_speeds(run)
        for r in rows:
            r["max_speed_m_s"] = speeds.get(r["stage"], math.nan)
        fast = [f"{r['name']} {r['max_speed_m_s']:.0f} m/s" for r in rows if r["max_speed_m_s"] > SUSPECT_SPEED]
        if fast:
            problems.append(f"{label(v)}: gridpoints faster than {SUSPECT_SPEED:.0f} m/s (numerical, not physical) in " +
                            ", ".join(fast) + ": read its results with care")
        data.append((v, rows))
        for k in rows[0]:
            if k.startswith("max_slip_near_") and k != "max_slip_near_m":
                s = k[len("max_slip_near_"):-2]
                if s not in sets:
                    sets.append(s)
    if not data:
        print("plot_drift_compare: no variant has results in " + out, file=sys.stderr)
        return 1

    # Event-by-event series.
    panels = [
        ("max_slip_near_m", "largest slip within 'near' of the wall [mm]", 1e3, False),
        ("fallen_blocks", "fallen blocks", 1.0, False),
        ("fallen_area_m2", "fallen area [m² per m of drift]", 1.0, False),
        ("loosened_extent_m", "loosened zone: reach from the wall [m]", 1.0, False),
        ("k_xx_ratio", "k_xx / reference", 1.0, True),
        ("k_yy_ratio", "k_yy / reference", 1.0, True),
        ("vertical_convergence_m", "vertical convergence [mm]", 1e3, False),
        ("horizontal_convergence_m", "horizontal convergence [mm]", 1e3, False),
    ]
    fig, axes = plt.subplots(4, 2, figsize=(11, 14))
    for ax, (key, yl, sc, lg) in zip(axes.flat, panels):
        series_plot(ax, data, key, yl, sc, lg)
    axes.flat[0].legend(fontsize=8)
    fig.suptitle("The same drift and earthquakes, joint model by joint model")
    fig.tight_layout()
    fig.savefig(os.path.join(figs, "events.png"), dpi=110)
    plt.close(fig)

    # Mean slip near the drift per joint set.
    fig, axes = plt.subplots(1, len(sets), figsize=(4.5 * len(sets), 4), squeeze=False)
    for ax, s in zip(axes.flat, sets):
        series_plot(ax, data, f"mean_slip_near_{s}_m", f"mean |slip| near the wall, set {s} [mm]", 1e3)
    axes.flat[0].legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(os.path.join(figs, "slip_by_set.png"), dpi=110)
    plt.close(fig)

    # Maps and histograms of slip after the last stage each run reached.
    near = read_near(os.path.join(out, data[0][0], "drift", "events.csv"))
    n = len(data)
    fig, axes = plt.subplots(2, n, figsize=(4.2 * n, 8), squeeze=False)
    last_files = []
    vmax = 0.0
    contacts = []
    for v, rows in data:
        r = rows[-1]
        path = os.path.join(out, v, "drift", f"contacts_{r['stage']}_{r['name']}.csv")
        contacts.append(read_drift_csv(path) if os.path.exists(path) else [])
        last_files.append(path)
    # One colour scale for all maps, to the 99th percentile of every model's slips (one block's
    # metre-scale slide would otherwise leave every other contact the same colour); the
    # histograms put everything above it in their last bin.
    every = sorted(abs(float(c["slip_m"])) * 1e3 for cs in contacts for c in cs)
    if every:
        vmax = every[min(len(every) - 1, int(0.99 * len(every)))]
    vmax = max(vmax, 0.1)
    for j, ((v, rows), cs) in enumerate(zip(data, contacts)):
        ax = axes[0][j]
        xs = [float(c["x_m"]) for c in cs]
        ys = [float(c["y_m"]) for c in cs]
        ss = [abs(float(c["slip_m"])) * 1e3 for c in cs]
        order = sorted(range(len(ss)), key=lambda i: ss[i])
        sc = ax.scatter([xs[i] for i in order], [ys[i] for i in order], c=[ss[i] for i in order], s=4,
                        cmap="viridis", vmin=0, vmax=vmax)
        ax.set_aspect("equal")
        ax.set_title(f"{label(v)}\nafter '{rows[-1]['name']}'", fontsize=9)
        ax.set_xlabel("x [m]")
        if j == 0:
            ax.set_ylabel("y [m]")
        fig.colorbar(sc, ax=ax, label="|slip| [mm]", shrink=0.7, extend="max")
        ax2 = axes[1][j]
        near_slips = [abs(float(c["slip_m"])) * 1e3 for c in cs if float(c["distance_to_wall_m"]) <= near]
        if near_slips:
            ax2.hist([min(x, vmax) for x in near_slips], bins=30, range=(0, vmax), color=COLORS[j % len(COLORS)])
            beyond = sum(x > vmax for x in near_slips)
            ax2.set_title(f"{len(near_slips)} near the wall; {beyond} over {vmax:.2g} mm;\nlargest {max(near_slips):.3g} mm",
                          fontsize=8)
        ax2.set_yscale("log")
        ax2.set_xlabel("|slip| near the wall [mm]")
        ax2.set_ylabel("contacts")
    fig.suptitle(f"Joint slip since the excavation after the last stage (colours and bins to the 99th percentile of "
                 f"all models, {vmax:.2g} mm; above it: the last bin)", fontsize=10)
    fig.tight_layout()
    fig.savefig(os.path.join(figs, "slip_maps.png"), dpi=110)
    plt.close(fig)

    # Summary table.
    cols = ["max_slip_near_m", "fallen_blocks", "fallen_area_m2", "loosened_extent_m", "loosened_contacts", "k_xx_ratio", "k_yy_ratio",
            "vertical_convergence_m", "horizontal_convergence_m", "max_speed_m_s"]
    with open(os.path.join(out, "summary.csv"), "w", newline="") as f:
        w = csv.writer(f, lineterminator="\n")
        w.writerow(["variant", "stage", "name", "kind"] + cols)
        for v, rows in data:
            for r in rows:
                w.writerow([v, r["stage"], r["name"], r["kind"]] + [r.get(c, "") for c in cols])

    def fmt(r, c):
        x = num(r, c)
        if math.isnan(x):
            return "—"
        if c.endswith("_m") and c not in ("loosened_extent_m",):
            return f"{x * 1e3:.2f} mm"
        if c == "loosened_extent_m":
            return f"{x:.2f} m"
        if c == "fallen_area_m2":
            return f"{x:.2f}"
        if c == "fallen_blocks":
            return f"{int(x)}"
        if c == "max_speed_m_s":
            return f"{x:.2g} m/s"
        return f"{x:.3g}"

    h = ["<!DOCTYPE html><html><head><meta charset='utf-8'><title>Drift comparison</title>",
         "<style>body{font-family:sans-serif;max-width:1200px;margin:2em auto}table{border-collapse:collapse}"
         "td,th{border:1px solid #ccc;padding:3px 8px;text-align:right}th{background:#eee}"
         ".bad{color:#b00;font-weight:bold}</style></head><body>",
         "<h1>The drift under repeated earthquakes, joint model by joint model</h1>",
         "<p>Each run is the same case, rock mass, excavation and event sequence; only the joints of the "
         "named joint sets differ (scripts/drift-compare, docs/drift-study.md). Everything is measured from the "
         "state after excavation. <code>max_speed_m_s</code> is the largest gridpoint speed sampled in the stage "
         "(the <code>max_speed</code> history): a block falling through the drift reaches about 10 m/s; far above "
         "that, the speed is numerical and the stage's results are suspect.</p>"]
    for p in problems:
        h.append(f"<p class='bad'>{html.escape(p)}</p>")
    h.append("<h2>Event by event</h2><img src='figures/events.png' width='100%'>")
    h.append("<img src='figures/slip_by_set.png' width='100%'>")
    h.append("<h2>Table</h2><table><tr><th>joints</th><th>after</th>" +
             "".join(f"<th>{html.escape(c)}</th>" for c in cols) + "</tr>")
    for v, rows in data:
        for r in rows:
            h.append(f"<tr><td>{html.escape(label(v))}</td><td>{html.escape(r['name'])}</td>" +
                     "".join(f"<td>{fmt(r, c)}</td>" for c in cols) + "</tr>")
    h.append("</table>")
    h.append("<h2>Slip after the last stage</h2><p>Maps: every joint contact, coloured by its slip since the "
             "excavation; histograms: the contacts within 'near' of the wall. Files: " +
             ", ".join(html.escape(os.path.relpath(p, out)) for p in last_files) + ".</p>")
    h.append("<img src='figures/slip_maps.png' width='100%'>")
    h.append("<h2>Runs</h2><ul>")
    for v, _ in data:
        status, cmd = run_status(os.path.join(out, v))
        h.append(f"<li>{html.escape(label(v))}: {html.escape(status)}; <code>{html.escape(cmd)}</code></li>")
    h.append("</ul></body></html>")
    with open(os.path.join(out, "index.html"), "w") as f:
        f.write("\n".join(h))
    print("wrote " + os.path.join(out, "index.html"))
    return 0


def read_near(path):
    """The 'near' distance the run used, from the '# ... within X m of its wall' header line."""
    with open(path) as f:
        for ln in f:
            if not ln.startswith("#"):
                break
            i = ln.find("within ")
            if i >= 0:
                try:
                    return float(ln[i + 7:].split()[0])
                except ValueError:
                    pass
    return math.inf


if __name__ == "__main__":
    sys.exit(main())
