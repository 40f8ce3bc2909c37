#!/usr/bin/env bash
# The drift comparison (scripts/drift-compare, docs/drift-study.md): the small drift study run
# with each of the four joint models of its default set (cases/drift/laws/). Checks:
#  - every run finishes and the report is written (index.html naming each model, its figures,
#    summary.csv with one row per model and stage from the excavation on);
#  - each run used its joint file (named in its manifest, copied into joints/) and the models
#    give different results (no two of them the same slip near the drift after the last event);
#  - regression: summary.csv against tests/cli/drift/compare_summary_gold.csv (fallen blocks
#    exactly, displacements to 0.5 mm + 5 %, extents to 0.1 m, permeability ratios to 10 %);
#  - no stage of any model has a gridpoint faster than 20 m/s (the report's flag);
#  - bad arguments to the script are refused (exit 2) naming them.
# Usage: bash drift_compare.sh <rockdem-binary> <source-dir>
set -u
bin=$1
src=$(cd "$2" && pwd)
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
fail=0
ok() { echo "ok   $1"; }
bad() { echo "FAIL $1"; fail=1; }

ROCKDEM_BIN=$bin "$src/scripts/drift-compare" --out "$tmp/c" > "$tmp/log" 2>&1
rc=$?
[ $rc -eq 0 ] && ok "scripts/drift-compare: exit 0, four runs" || { bad "scripts/drift-compare exited $rc"; cat "$tmp/log"; }
for v in mohr_coulomb barton_bandis continuously_yielding continuously_yielding_reverse_wear; do
  grep -q -- "--joint joints=$src/cases/drift/laws/$v.toml" "$tmp/c/$v/manifest.json" 2>/dev/null \
    && cmp -s "$src/cases/drift/laws/$v.toml" "$tmp/c/$v/joints/joints.toml" \
    && ok "$v: run with its joint file (manifest, joints/joints.toml)" || bad "$v: manifest or joints/ does not show its joint file"
done
/usr/bin/python3 - "$tmp/c" "$src/tests/cli/drift/compare_summary_gold.csv" <<'PY' || fail=1
import csv, math, os, sys
out, gold_path = sys.argv[1:3]
fail = False
def check(good, what):
    global fail
    print(("ok   " if good else "FAIL ") + what)
    fail = fail or not good
page = open(os.path.join(out, "index.html")).read()
check(all(s in page for s in ("Mohr-Coulomb", "Barton-Bandis", "Continuously-Yielding", "CY + reverse-shear degradation")),
      "index.html names the four joint models")
figs = ["events.png", "slip_by_set.png", "slip_maps.png"]
check(all(os.path.getsize(os.path.join(out, "figures", f)) > 10000 for f in figs) and all(f in page for f in figs),
      "index.html shows its figures: " + ", ".join(figs))
rows = list(csv.DictReader(open(os.path.join(out, "summary.csv"))))
variants = sorted({r["variant"] for r in rows})
check(len(rows) == 4 * 5 and len(variants) == 4, f"summary.csv: {len(rows)} rows, 5 stages for each of {len(variants)} models")
last = {r["variant"]: r for r in rows if r["name"] == "rest_2"}
slips = {v: float(last[v]["max_slip_near_m"]) for v in last}
distinct = all(abs(slips[a] - slips[b]) > 1e-6 for a in slips for b in slips if a < b)
check(distinct, "no two models give the same slip near the drift: " +
      ", ".join(f"{v} {1e3 * s:.2f} mm" for v, s in sorted(slips.items())))
fast = [f"{r['variant']} {r['name']} {float(r['max_speed_m_s']):.1f} m/s" for r in rows if float(r["max_speed_m_s"]) >= 20.0]
check(not fast, "no stage of any model has a gridpoint faster than 20 m/s (a numerical episode)" + ("" if not fast else ": " + ", ".join(fast)))
gold = list(csv.DictReader(open(gold_path)))
check([(g["variant"], g["name"]) for g in gold] == [(r["variant"], r["name"]) for r in rows], "the same models and stages as the gold file")
worst = []
for g, r in zip(gold, rows):
    for k in g:
        if k in ("variant", "stage", "name", "kind", "max_speed_m_s"):  # speed: a check shown in the report, not a result
            continue
        a, b = float(r[k]), float(g[k])
        if math.isnan(a) and math.isnan(b):
            continue
        if k == "fallen_blocks":
            good = a == b
        elif k.endswith("_ratio"):
            good = abs(a - b) <= 0.10 * abs(b) + 1e-9
        elif k == "loosened_extent_m":
            good = abs(a - b) <= 0.1
        elif k == "fallen_area_m2":
            good = abs(a - b) <= 0.01 + 0.01 * abs(b)
        else:
            good = abs(a - b) <= 5e-4 + 0.05 * abs(b)
        if not good:
            worst.append(f"{r['variant']} {r['name']} {k}: {a:.6g} (gold {b:.6g})")
check(not worst, "summary.csv matches the gold file within its tolerances" + ("" if not worst else ": " + "; ".join(worst[:8])))
sys.exit(1 if fail else 0)
PY

# Bad arguments.
for args in "--np two" "--jobs 0" "--case $tmp/none.toml" "--laws $tmp/none.toml" "--bogus"; do
  # shellcheck disable=SC2086
  msg=$(ROCKDEM_BIN=$bin "$src/scripts/drift-compare" $args --out "$tmp/bad" 2>&1)
  rc=$?
  word=${args%% *}
  [ $rc -eq 2 ] && printf '%s' "$msg" | grep -q -- "${word#--}" && ok "drift-compare $args: exit 2, $(printf '%s' "$msg" | head -n 1)" \
    || bad "drift-compare $args: exit $rc: $msg"
done
exit $fail
