#!/usr/bin/env bash
# Bad input to a drift study (cases/drift/small.toml, issue 14): an earthquake scaled beyond any
# recorded one (a PGV or a motion_scale that is a slip of a unit or a digit), an event that names
# no motion (an empty event list), a record whose time column is in milliseconds (a sample every
# 20 s), a joint calibrated for another law: each stops before running (exit 2) with a message
# that names the key and says what to change. A [drift] table with no earthquake at all is not bad
# input: tests/cli/drift/results.toml reports static stages (a strength reduction) with it. Nor
# are free-field columns with free tops under the quiet top: they are warned of (the study had
# them until 2026-12-01, docs/drift-study.md), and with the study's quiet column tops nothing is
# said.
# Usage: bash drift_bad_input.sh <rockdem-binary> <source-dir>
set -u
bin=$1
src=$(cd "$2" && pwd)
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
fail=0
. "$src/tests/cli/lib/expect.sh"
# The study with its record found from anywhere.
sed "s|file = \"../data/|file = \"$src/cases/data/|" "$src/cases/drift/small.toml" > "$tmp/study.toml"
variant() {  # variant NAME SED-EXPRESSION: a copy of the study with one change
  sed "$2" "$tmp/study.toml" > "$tmp/$1.toml"
  cmp -s "$tmp/study.toml" "$tmp/$1.toml" && { echo "FAIL variant $1 changed nothing"; fail=1; }
}
variant pgv '0,/^pgv = "0.5 m\/s"/s//pgv = "50 m\/s"/'
line=$(grep -n -m1 '^pgv = "50 m/s"' "$tmp/pgv.toml" | cut -d: -f1)  # the message names the key's own line
expect "PGV 50 m/s" 2 run "$tmp/pgv.toml" --out "$tmp/o1" -- \
  "pgv.toml:$line key 'stages.event_1.pgv'" "PGV 50 m/s (more than 5 m/s)" "beyond any recorded earthquake" "Check the unit"
variant scale '0,/^pgv = "0.5 m\/s"/s//motion_scale = 100/'
expect "motion_scale 100" 2 run "$tmp/scale.toml" --out "$tmp/o2" -- \
  "key 'stages.event_1.motion_scale'" "PGA 34.9" "scaled by 100"
variant empty '0,/^motion = "elcentro"/s//motion = []/'
expect "an event with no motion" 2 run "$tmp/empty.toml" --out "$tmp/o4" -- \
  "key 'stages.event_1.motion': name at least one [[motions]] entry"
# The record's time column in milliseconds.
awk -F, 'NR == 1 { print; next } { printf "%g,%s\n", $1 * 1000, $2 }' "$src/cases/data/ground_motions/elcentro1940_ns_acc_g.csv" > "$tmp/ms.csv"
sed "s|file = \".*elcentro1940_ns_acc_g.csv\"|file = \"$tmp/ms.csv\"|; s|^window = .*||" "$tmp/study.toml" > "$tmp/coarse.toml"
expect "a record sampled every 20 s" 2 run "$tmp/coarse.toml" --out "$tmp/o7" -- \
  "[motions] 'elcentro': the record is sampled every 20 s" "too coarse for an earthquake record" "milliseconds read as seconds"
printf '{"law": "barton_bandis", "status": "converged", "params": {"jrc": 7.0}}\n' > "$tmp/bb.json"
variant calib "s|^law = \"coulomb_slip\"\njoint_sets = \[\"steep_1\"|&|; 0,/^name = \"joints\"/s||name = \"joints\"\ncalibration = \"$tmp/bb.json\"|"
expect "a calibration for another law than the joint set's" 2 run "$tmp/calib.toml" --out "$tmp/o5" -- \
  "key 'joints.joints.law': law 'coulomb_slip' but the calibration" "is of a barton_bandis joint" "remove 'law'"
# Building the blocks (--write-blocks) reads the whole case without running it.
variant free_tops '/^top = "quiet"/d'
# The lines of the [[boundary]] headers of the two columns and of the quiet top, as the file has them.
read -r left right quiet < <(awk '/^\[\[boundary\]\]/ { at = NR } /^type = "free_field"/ { ff = ff " " at }
  /^type = "quiet"/ { q = at } END { print ff, q }' "$tmp/free_tops.toml")
expect "free column tops under a quiet model top" 0 run "$tmp/free_tops.toml" --write-blocks "$tmp/b1" -- \
  "rockdem: warning: $tmp/free_tops.toml:$left [boundary] (free_field, left side): its column's top is \"free\" but the model's top is quiet (the quiet boundary $tmp/free_tops.toml:$quiet [boundary]) in stages 'event_1', 'event_2'" \
  "rockdem: warning: $tmp/free_tops.toml:$right [boundary] (free_field, right side)" "set top = \"quiet\" in this boundary"
# Another level or record for the events from the command line (rockdem run --pgv, --motion):
# checked as the case file's own keys are, before anything runs.
expect "--pgv beyond any recorded earthquake" 2 run "$tmp/study.toml" --out "$tmp/o8" --pgv "50 m/s" -- \
  "key 'stages.event_1.pgv' (a value not read from the file: given on the command line" "PGV 50 m/s (more than 5 m/s)"
expect "--pgv without a unit" 2 run "$tmp/study.toml" --out "$tmp/o9" --pgv event_2=1 -- \
  "--pgv event_2=1: '1' has no unit; a velocity needs one of: m/s" "e.g. \"0.5 m/s\""
expect "--pgv for a stage that plays no motion" 2 run "$tmp/study.toml" --out "$tmp/o10" --pgv "rest_1=1 m/s" -- \
  "--pgv rest_1=1 m/s: stage 'rest_1'" "plays no motion" "stages that play one: event_1, event_2"
expect "--pgv for a stage the case lacks" 2 run "$tmp/study.toml" --out "$tmp/o11" --pgv "event_3=1 m/s" -- \
  "has no stage 'event_3' (did you mean 'event_1'?); its stages: in_situ, excavate, event_1, rest_1, event_2, rest_2"
expect "--motion naming no [[motions]] entry" 2 run "$tmp/study.toml" --out "$tmp/o12" --motion event_2=nortridge -- \
  "key 'stages.event_2.motion'" "no motion named 'nortridge'" "motions: elcentro, northridge"
expect "--motion given twice for one stage" 2 run "$tmp/study.toml" --out "$tmp/o13" --motion event_1=northridge \
  --motion event_1=elcentro -- "stage 'event_1' is given a motion twice"
expect "--motion on a laboratory-test case" 2 run "$src/cases/direct_shear/test09_mohr_coulomb.toml" --out "$tmp/o14" \
  --motion northridge -- "--motion and --pgv apply to DEM case files"
out=$("$bin" run "$tmp/study.toml" --write-blocks "$tmp/b2" 2>&1)
code=$?
if [ $code -ne 0 ] || grep -q "warning" <<<"$out"; then
  echo "FAIL quiet column tops under the quiet model top: exit $code, wanted 0 and no warning: $out"
  fail=1
else
  echo "ok   quiet column tops under the quiet model top: no warning"
fi
for d in o1 o2 o4 o5 o7 o8 o9 o10 o11 o12 o13 o14; do
  [ -e "$tmp/$d/history.h5" ] && { echo "FAIL $d: a refused case started running"; fail=1; }
done
exit $fail
