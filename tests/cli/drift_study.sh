#!/usr/bin/env bash
# The small drift study (cases/drift/small.toml, issue 14): in-situ stress, excavation, two
# earthquakes each followed by a return to equilibrium. Checks:
#  - the run completes its six stages and writes a row of results per stage from the excavation on;
#  - the rock mass rides the ground: the base's displacement over each event is the incident
#    wave's residual displacement, half the outcrop record's (within 5 %), and the results' frame
#    moves with it;
#  - no event turns the model as a whole (the frame by less than 1e-4 rad; 2.15 mrad while the
#    free-field columns' tops were free);
#  - the returns to equilibrium move nothing of the frame (below 1 mm);
#  - both events and the returns after them stay below 20 m/s everywhere (the max_speed history),
#    and each return reaches equilibrium unless a block has come loose by its end;
#  - regression: events.csv against tests/cli/drift/small_events_gold.csv (displacements to
#    0.2 mm, permeability ratios to 5 %, counts exactly);
#  - the energy balance over each event closes within 2 % (0.31 % and 0.97 % when measured,
#    docs/drift-study.md), and the change the contact refreshes make to the stored energy with
#    no force doing it (the history component `refresh`) stays below 5 % of the largest term
#    (1.5 % and 0.03 %, mostly contacts' lengths shared out again as points move; 1.18 % and
#    1.00 % closure without that change). Before closed contacts kept their face past an edge's
#    end and their joint model at a rock bridge's end: 0.05 % and 1.56 %, the refreshes 0.66 %
#    and 4.1 % (docs/drift-study.md, "Not done yet");
#  - two processes give the same events.csv, bit for bit;
#  - no shaking, no motion: with the first event's input taken away the drift's crown moves less
#    than 0.01 mm over 0.5 s and no block falls.
# Usage: bash drift_study.sh <rockdem-binary> <source-dir>
set -u
bin=$1
src=$2
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_rmaps_base_oversubscribe=1
fail=0
case_file=$src/cases/drift/small.toml
# The case with the energy balance's terms recorded (its ground motion found from the copy).
/usr/bin/python3 - "$case_file" "$tmp/energy.toml" <<'PY'
import sys
s = open(sys.argv[1]).read()
s = s.replace('"../data/ground_motions', '"' + sys.argv[1].rsplit("/", 2)[0] + '/data/ground_motions')
for t in ("kinetic", "strain", "contact", "gravity_work", "boundary_work", "slip", "damping", "imbalance", "refresh"):
    s += f'\n[[histories]]\nname = "energy_{t}"\nquantity = "energy"\ncomponent = "{t}"\n'
open(sys.argv[2], "w").write(s)
PY

"$bin" run "$tmp/energy.toml" --out "$tmp/s" --quiet || { echo "FAIL run exited $?"; exit 1; }
/usr/bin/python3 "$src/scripts/energy_by_stage.py" "$tmp/s" || { echo "FAIL energy_by_stage.py"; fail=1; }
/usr/bin/python3 - "$src/scripts" "$tmp/s" <<'PY' || fail=1
import sys
sys.path.insert(0, sys.argv[1])
from energy_by_stage import stage_changes
rows = {s: (d, scale, closure, without) for s, d, scale, closure, without in stage_changes(sys.argv[2])}
bad = False
for stage, name in ((3, "event_1"), (5, "event_2")):
    d, scale, closure, without = rows[stage]
    share = abs(d['refresh']) / scale
    good = closure < 0.02 and share < 0.05
    print(("ok   " if good else "FAIL ") + f"{name}: the energy balance closes to {closure:.2%} (2 % asked); the contact "
          f"refreshes changed the stored energy by {d['refresh']:.4g} J/m, {share:.2%} of the largest term (5 % allowed; "
          f"{without:.2%} closure without that change)")
    bad = bad or not good
sys.exit(1 if bad else 0)
PY
PYTHONPATH="$src/tests/cli/lib" /usr/bin/python3 - "$tmp/s" "$src/tests/cli/drift/small_events_gold.csv" <<'PY' || fail=1
import sys, csv, h5py, numpy as np
out, gold_path = sys.argv[1:3]
from checks import check, done, rows
ev = rows(out + "/drift/events.csv")
check([r["kind"] for r in ev] == ["reference", "event", "rest", "event", "rest"], "events.csv: the reference, two events, two rests")
# The base rides the incident wave. The record is an outcrop motion (twice the wave going up), and
# the model's top and its free-field columns' tops are quiet: the wave leaves through the top and
# no reflection of it comes back down, so the base ends displaced by half the record's residual
# displacement (with the columns' tops free it took the whole of it, and the model turned).
for n, stage, before in ((3, "event_1", "stage_2_excavate"), (5, "event_2", "stage_4_rest_1")):
    lines = open(f"{out}/motion_{n}_{stage}.csv").readlines()
    described = [l for l in lines if l.startswith("# motion:")]
    check(len(described) == 1 and "| type: outcrop |" in described[0], f"{stage}: one motion, an outcrop motion")
    data = [l.strip().split(",") for l in lines if not l.startswith("#")]
    residual = 0.5 * float(data[-1][data[0].index("elcentro_disp_m")])
    with h5py.File(f"{out}/{before}.h5", "r") as a, h5py.File(f"{out}/stage_{n}_{stage}.h5", "r") as b:
        x0 = a["gridpoints/x0"][:]
        base = np.abs(x0[:, 1] + 15) < 1e-3
        moved = (b["gridpoints/x"][:] - a["gridpoints/x"][:])[base, 0].mean()
    check(abs(moved - residual) < 0.05 * abs(residual),
          f"{stage}: the base moved {moved:.4f} m, the incident wave's residual displacement {residual:.4f} m")
# Nothing turns the model as a whole: each event turns the far field's frame by micro-radians
# (2 mrad per event while the free-field columns' tops were free under the quiet top).
for k in (1, 3):
    turn = abs(float(ev[k]["frame_rotation_rad"]) - float(ev[k - 1]["frame_rotation_rad"]))
    check(turn < 1e-4, f"{ev[k]['name']}: the frame turned {turn:.3g} rad")
for k in (2, 4):
    dx = abs(float(ev[k]["frame_x_m"]) - float(ev[k - 1]["frame_x_m"]))
    dy = abs(float(ev[k]["frame_y_m"]) - float(ev[k - 1]["frame_y_m"]))
    check(dx < 1e-3 and dy < 1e-3, f"{ev[k]['name']}: the frame moved {dx * 1e3:.3f}, {dy * 1e3:.3f} mm in the return to equilibrium")
# No numerical episode in either event or the returns after them: every gridpoint slower than
# 20 m/s (a block falling through the drift reaches about 10 m/s; before the deep-contact fix a
# corner sinking into a neighbour on a contact of zero length kicked the sidewall at 75 m/s in the
# second event).
with h5py.File(out + "/history.h5", "r", locking=False) as f:
    st, sp = f["history/stage"][:], f["history/max_speed"][:]
for s in (3, 4, 5, 6):
    top = sp[st == s].max()
    check(top < 20.0, f"stage {s}: the fastest gridpoint {top:.2f} m/s")
# Each return to equilibrium reaches the case's ratio (1e-5), unless a block has come loose by its
# end (at_max_steps = "continue" ends it at max_steps with the block still sliding out, a result).
for k in (2, 4):
    r = float(ev[k]["unbalanced_ratio"])
    loose = float(ev[k]["fallen_blocks"]) > 0
    check(r <= 1e-5 or loose, f"{ev[k]['name']}: " + (f"equilibrium reached (ratio {r:.3g})" if r <= 1e-5 else
          f"ratio {r:.3g} with a loosened block still moving"))
# Regression against the gold file.
gold = rows(gold_path)
check(len(gold) == len(ev) and list(gold[0].keys()) == list(ev[0].keys()), "the same rows and columns as the gold file")
worst = []
for g, r in zip(gold, ev):
    for k in g:
        if k in ("stage", "name", "kind"):
            ok = g[k] == r[k]
        elif k.endswith("_m2"):
            continue  # the ratios below carry the permeability
        elif k.endswith("_ratio"):
            ok = abs(float(r[k]) - float(g[k])) <= 0.05 * abs(float(g[k]))
        elif k in ("fallen_blocks", "loosened_contacts"):
            ok = abs(float(r[k]) - float(g[k])) <= (0 if k == "fallen_blocks" else max(3, 0.1 * float(g[k])))
        elif k == "frame_rotation_rad":
            ok = abs(float(r[k]) - float(g[k])) <= 1e-5
        elif k == "time_s":
            ok = abs(float(r[k]) - float(g[k])) <= 0.05 * float(g[k])
        elif np.isnan(float(g[k])) or np.isnan(float(r[k])):
            ok = np.isnan(float(g[k])) and np.isnan(float(r[k]))  # no wall point left there (fallen)
        else:
            ok = abs(float(r[k]) - float(g[k])) <= 2e-4
        if not ok:
            worst.append(f"{r['name']} {k}: {r[k]} (gold {g[k]})")
check(not worst, "events.csv matches the gold file within its tolerances" + ("" if not worst else ": " + "; ".join(worst[:6])))
done()
PY

# Two processes.
mpirun -np 2 "$bin" run "$tmp/energy.toml" --out "$tmp/p2" --quiet > "$tmp/p2.log" 2>&1 || { cat "$tmp/p2.log"; echo "FAIL 2-process run"; fail=1; }
if cmp -s "$tmp/s/drift/events.csv" "$tmp/p2/drift/events.csv"; then echo "ok   2 processes: events.csv identical"
else echo "FAIL 2 processes: events.csv differs"; diff "$tmp/s/drift/events.csv" "$tmp/p2/drift/events.csv" | head -6; fail=1; fi

# No shaking: the first event without its input, half a second, and nothing after it.
/usr/bin/python3 - "$tmp/energy.toml" "$tmp/quiet.toml" <<'PY'
import sys
s = open(sys.argv[1]).read()
head, rest = s.split('[[stages]]\nname = "event_1"', 1)
event, after = rest.split("[[stages]]", 1)
event = event.replace('motion = "elcentro"\npgv = "0.5 m/s"\nduration = "auto"', 'duration = "0.5 s"')
hist = after[after.index("[[histories]]"):]
s = head + '[[stages]]\nname = "event_1"' + event + hist
s = s.replace('stages = ["in_situ", "excavate", "rest_1", "rest_2"]', 'stages = ["in_situ", "excavate"]')
s = s.replace('stages = ["event_1", "event_2"]', 'stages = ["event_1"]')
open(sys.argv[2], "w").write(s)
PY
"$bin" run "$tmp/quiet.toml" --out "$tmp/q" --quiet || { echo "FAIL no-shaking run exited $?"; fail=1; }
/usr/bin/python3 - "$tmp/q" <<'PY' || fail=1
import sys, csv, h5py, numpy as np
out = sys.argv[1]
with h5py.File(out + "/history.h5", "r", locking=False) as f:
    h = f["history"]
    st, cy = h["stage"][:], h["crown_y"][:]
moved = np.abs(cy[st == 3] - cy[st == 3][0]).max()
ev = list(csv.DictReader(l for l in open(out + "/drift/events.csv") if not l.startswith("#")))
good = moved < 1e-5 and ev[-1]["fallen_blocks"] == "0"
print(("ok   " if good else "FAIL ") + f"no shaking: the crown moved {moved * 1e6:.3f} um in 0.5 s, {ev[-1]['fallen_blocks']} blocks fell")
sys.exit(0 if good else 1)
PY
exit $fail
