#!/usr/bin/env bash
# Joints from files (docs/case-files.md#joints, `rockdem run --joint`), on the small jointed rock
# mass of tests/cli/drift/results.toml. Checks:
#  - `--joint joints=FILE` with FILE holding the entry's own law and parameters gives the same
#    results bit for bit (the replacement is exact), names FILE in the manifest's command line
#    and copies it into <out>/joints/;
#  - a joint fitted by `rockdem calibrate` (its JSON) named in the case (`calibration = ...`) and
#    given as `--joint joints=fit.json` is the same joint (same results bit for bit), and not the
#    case's own (other results);
#  - `at_max_steps = "continue"` ends an equilibrium stage at max_steps with a warning and goes
#    on, and events.csv gives the ratio reached; without it the run stops with exit code 3;
#  - bad input: an unknown joint name, a missing file, NAME=FILE malformed or given twice, a
#    joint file that says where the joint acts, a calibration of another law than the case's
#    entry, an unknown parameter in a joint file, a bad at_max_steps, --joint on a laboratory
#    case: each exits 2 naming the file, key or name and what is valid.
# Usage: bash joint_files.sh <rockdem-binary> <source-dir>
set -u
bin=$1
src=$2
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
fail=0
case_file=$src/tests/cli/drift/results.toml
ok() { echo "ok   $1"; }
bad() { echo "FAIL $1"; fail=1; }
same() {  # same <what> <dir a> <dir b>: every drift file identical (but the '#' lines naming the case file)
  local f d=0
  for f in "$2"/drift/*.csv; do
    cmp -s <(grep -v '^#' "$f") <(grep -v '^#' "$3/drift/$(basename "$f")") || { d=1; bad "$1: $(basename "$f") differs"; }
  done
  [ $d -eq 0 ] && ok "$1: every drift/ file identical ($(ls "$2"/drift | wc -l) files)"
}

# The case's own joint, from a file.
cat > "$tmp/own.toml" <<'EOF'
# the [[joints]] entry 'joints' of tests/cli/drift/results.toml, as a joint file
law = "coulomb_slip"
kn = "5 GPa/m"
ks = "2 GPa/m"
friction = "5 deg"
EOF
"$bin" run "$case_file" --out "$tmp/plain" --quiet || bad "plain run exited $?"
"$bin" run "$case_file" --joint "joints=$tmp/own.toml" --out "$tmp/own" --quiet || bad "--joint run exited $?"
same "--joint with the entry's own joint" "$tmp/plain" "$tmp/own"
grep -q -- "--joint joints=$tmp/own.toml" "$tmp/own/manifest.json" && ok "the manifest's command line names the joint file" \
  || bad "the manifest does not name the joint file"
cmp -s "$tmp/own.toml" "$tmp/own/joints/joints.toml" && ok "the joint file is copied into <out>/joints/" || bad "joints/joints.toml missing or different"

# A calibrated joint: rockdem calibrate's JSON, in the case and on the command line.
"$bin" calibrate --data "$src/cases/direct_shear/twins/test09.csv" --law mohr_coulomb \
  --case "$src/cases/direct_shear/test09_mohr_coulomb.toml" --json "$tmp/fit.json" --quiet || bad "calibrate exited $?"
grep -q '"dilation": "udec_legacy"' "$tmp/fit.json" && ok "calibrate's JSON records the settings it ran with (dilation mode)" \
  || bad "no settings in calibrate's JSON"
# (The stiffer, dilating joint settles more slowly: its in-situ stage may end at max_steps.)
/usr/bin/python3 - "$case_file" "$tmp/base.toml" "$tmp/calibrated.toml" "$tmp/fit.json" <<'PY'
import sys
src, base, dst, fit = sys.argv[1:5]
text = open(src).read().replace("max_steps = 5000\n", 'max_steps = 5000\nat_max_steps = "continue"\n', 1)
old = 'name = "joints"\nlaw = "coulomb_slip"\njoint_sets = ["steep", "flat"]\nkn = "5 GPa/m"\nks = "2 GPa/m"\nfriction = "5 deg"'
assert old in text and "at_max_steps" in text, "results.toml's joints entry or in_situ stage changed: update this test"
open(base, "w").write(text)
open(dst, "w").write(text.replace(old, f'name = "joints"\njoint_sets = ["steep", "flat"]\ncalibration = "{fit}"'))
PY
"$bin" run "$tmp/calibrated.toml" --out "$tmp/cal_case" --quiet 2> /dev/null || bad "case with calibration = ... exited $?"
"$bin" run "$tmp/base.toml" --joint "joints=$tmp/fit.json" --out "$tmp/cal_cli" --quiet 2> /dev/null || bad "--joint joints=fit.json exited $?"
same "calibration in the case and --joint fit.json" "$tmp/cal_case" "$tmp/cal_cli"
if cmp -s "$tmp/plain/drift/events.csv" "$tmp/cal_cli/drift/events.csv"; then
  bad "the calibrated joint gave the case's own results: it was not used"
else
  ok "the calibrated joint (Mohr-Coulomb, 34.7 deg) gives other results than the case's 5 deg Coulomb joint"
fi

# at_max_steps: an equilibrium stage that cannot converge in 300 steps.
sed 's/^ratio = 1e-4$/ratio = 1e-12/; s/^max_steps = 5000$/max_steps = 300\nat_max_steps = "continue"/' "$case_file" > "$tmp/cont.toml"
grep -q 'at_max_steps = "continue"' "$tmp/cont.toml" || bad "could not make the at_max_steps case"
"$bin" run "$tmp/cont.toml" --out "$tmp/cont" --quiet 2> "$tmp/cont.err"
rc=$?
if [ $rc -eq 0 ] && grep -q "warning: stage 'in_situ' ended at max_steps = 300 without equilibrium" "$tmp/cont.err"; then
  ok "at_max_steps = \"continue\": exit 0, warning: $(head -n 1 "$tmp/cont.err" | cut -c1-110)"
else
  bad "at_max_steps = \"continue\": exit $rc, stderr: $(cat "$tmp/cont.err")"
fi
ratio=$(/usr/bin/python3 -c "
import csv,sys
r=list(csv.DictReader(l for l in open('$tmp/plain/drift/events.csv') if not l.startswith('#')))
print(all(0 <= float(x['unbalanced_ratio']) < 1 for x in r))")
[ "$ratio" = True ] && ok "events.csv gives each stage's unbalanced-force ratio" || bad "events.csv: unbalanced_ratio missing or out of range"
sed 's/^at_max_steps = "continue"$//' "$tmp/cont.toml" > "$tmp/stop.toml"
"$bin" run "$tmp/stop.toml" --out "$tmp/stop" --quiet 2> "$tmp/stop.err"
rc=$?
[ $rc -eq 3 ] && grep -q 'at_max_steps = "continue" ends the stage there' "$tmp/stop.err" \
  && ok "without it: exit 3, and the message says how to go on" || bad "without at_max_steps: exit $rc: $(cat "$tmp/stop.err")"

# Bad input: exit 2 and a message naming what is wrong and what is valid.
. "$src/tests/cli/lib/expect.sh"
n=0
out() { n=$((n + 1)); echo "$tmp/bad$n"; }
expect "unknown joint name" 2 run "$case_file" --joint "joint=$tmp/own.toml" --out "$(out)" --quiet -- \
  "has no [[joints]] entry 'joint'" "did you mean 'joints'" "its joints: joints, other"
expect "missing joint file" 2 run "$case_file" --joint "joints=$tmp/nope.toml" --out "$(out)" --quiet -- \
  "joint file '$tmp/nope.toml' does not exist"
expect "NAME=FILE malformed" 2 run "$case_file" --joint "joints" --out "$(out)" --quiet -- "write NAME=FILE"
expect "a joint given twice" 2 run "$case_file" --joint "joints=$tmp/own.toml" --joint "joints=$tmp/fit.json" --out "$(out)" --quiet -- \
  "joint 'joints' is given twice"
printf 'law = "coulomb_slip"\nkn = "5 GPa/m"\nks = "2 GPa/m"\nfriction = "5 deg"\njoint_sets = ["flat"]\n' > "$tmp/where.toml"
expect "a joint file that says where it acts" 2 run "$case_file" --joint "joints=$tmp/where.toml" --out "$(out)" --quiet -- \
  "$tmp/where.toml:5" "where it acts ('joint_sets') stays as in"
printf 'law = "coulomb_slip"\nkn = "5 GPa/m"\nks = "2 GPa/m"\nfrction = "5 deg"\n' > "$tmp/typo.toml"
expect "an unknown parameter in a joint file" 2 run "$case_file" --joint "joints=$tmp/typo.toml" --out "$(out)" --quiet -- \
  "$tmp/typo.toml:4" "unknown parameter 'frction'" "did you mean 'friction'"
printf 'law = "barton_bandis"\ncalibration = "fit.json"\n' > "$tmp/mismatch.toml"
expect "a calibration of another law" 2 run "$case_file" --joint "joints=$tmp/mismatch.toml" --out "$(out)" --quiet -- \
  "$tmp/mismatch.toml:1" "law 'barton_bandis' but the calibration" "is of a mohr_coulomb joint"
sed 's/^at_max_steps = "continue"$/at_max_steps = "maybe"/' "$tmp/cont.toml" > "$tmp/maybe.toml"
expect "a bad at_max_steps" 2 run "$tmp/maybe.toml" --out "$(out)" --quiet -- \
  "key 'stages.in_situ.at_max_steps': must be \"fail\"" "or \"continue\"" "not 'maybe'"
expect "--joint on a laboratory case" 2 run "$src/cases/direct_shear/test09_mohr_coulomb.toml" --joint "joints=$tmp/own.toml" --out "$(out)" --quiet -- \
  "--joint applies to DEM case files"
exit $fail
