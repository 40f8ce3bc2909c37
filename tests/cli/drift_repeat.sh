#!/usr/bin/env bash
# Repeating an event with joints that stay elastic gives back the same response (issue 14): the
# small drift study (cases/drift/small.toml) with every joint glued (1 GPa cohesion and tension,
# tests/cli/drift/make_elastic.py --glued), through both events of the same record and their
# returns to equilibrium. Nothing should accumulate from one event to the next:
#  - both events and rests run, no gridpoint faster than 2 m/s (0.37 m/s measured 2026-12-01);
#  - the energy balance of each event closes within 2 % (1.17 % and 1.03 % measured);
#  - the largest slip near the drift after event 2 within 5 % of that after event 1 (0.100 and
#    0.101 mm measured), and the permeability ratios within 1 % of the reference after each stage;
#  - the right springline's horizontal history (riding the ground's 0.1 m) in event 2, from the
#    event's start, that of event 1 to 1e-3 of its largest excursion (3.7e-5 measured), and the
#    crown's vertical history (a 34 um excursion) to 20 % of it (9 % measured; 39 % before closed
#    contacts kept their joint model at a rock bridge's end, when bridges were started afresh).
# Usage: bash drift_repeat.sh <rockdem-binary> <source-dir>
set -u
bin=$1
src=$(cd "$2" && pwd)
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
/usr/bin/python3 "$src/tests/cli/drift/make_elastic.py" "$src/cases/drift/small.toml" "$tmp/glued.toml" --glued || exit 1
"$bin" run "$tmp/glued.toml" --out "$tmp/g" --quiet --no-plots || { echo "FAIL run exited $?"; exit 1; }
/usr/bin/python3 - "$tmp/g" "$src/scripts" <<'PY'
import csv, sys, h5py, numpy as np
out = sys.argv[1]
sys.path.insert(0, sys.argv[2])
from energy_by_stage import stage_changes
results = []  # (holds, what), printed at the end
check = lambda good, what: results.append((bool(good), what))
rows = {r["name"]: r for r in csv.DictReader(l for l in open(out + "/drift/events.csv") if not l.startswith("#"))}
check(all(n in rows for n in ("event_1", "rest_1", "event_2", "rest_2")), "both events and their rests ran: " + ", ".join(rows))
with h5py.File(out + "/history.h5", "r", locking=False) as f:
    h = f["history"]
    st, sp = h["stage"][:], h["max_speed"][:]
    hist = {k: h[k][:] for k in ("springline_x", "crown_y")}
stage_of = {n: int(rows[n]["stage"]) for n in rows}
check(sp[st >= stage_of["event_1"]].max() < 2.0, f"fastest gridpoint from event 1 on {sp[st >= stage_of['event_1']].max():.3g} m/s (below 2 m/s)")
closures = {stage: (scale, closure) for stage, _, scale, closure, _ in stage_changes(out)}
for n in ("event_1", "event_2"):
    scale, closure = closures[stage_of[n]]
    check(closure <= 0.02, f"{n}: energy balance closes to {closure:.2%} of {scale:.4g} J/m (2 %)")
s1, s2 = float(rows["event_1"]["max_slip_near_m"]), float(rows["event_2"]["max_slip_near_m"])
check(abs(s2 - s1) <= 0.05 * s1 + 1e-6, f"largest slip near the drift {s1 * 1e3:.4f} mm after event 1, {s2 * 1e3:.4f} mm after event 2 (within 5 %)")
for n in ("event_1", "rest_1", "event_2", "rest_2"):
    kx, ky = float(rows[n]["k_xx_ratio"]), float(rows[n]["k_yy_ratio"])
    check(abs(kx - 1) <= 0.01 and abs(ky - 1) <= 0.01, f"{n}: permeability x {kx:.4f}, y {ky:.4f} of the reference (within 1 %)")
for name, tol in (("springline_x", 1e-3), ("crown_y", 0.2)):
    a = [hist[name][st == stage_of[n]] for n in ("event_1", "event_2")]
    a = [x - x[0] for x in a]
    k = min(len(x) for x in a)
    diff, peak = np.abs(a[1][:k] - a[0][:k]).max(), np.abs(a[0][:k]).max()
    check(k > 100 and diff <= tol * peak,
          f"{name}: event 2 repeats event 1 to {diff:.3g} m of a {peak:.3g} m excursion ({diff / peak:.2g}; {tol:g} allowed; {k} samples)")
for good, what in results:
    print(("ok   " if good else "FAIL ") + what)
sys.exit(0 if all(good for good, _ in results) else 1)
PY
