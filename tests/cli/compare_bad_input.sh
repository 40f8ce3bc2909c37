#!/usr/bin/env bash
# `rockdem compare` on bad input: broken measurement files are rejected with file, line and rule;
# records with other stages or incompatible shear paths are refused saying what differs; all with
# exit code 2. A good pair compares with exit 0 and writes the JSON.
# Usage: bash compare_bad_input.sh <rockdem-binary> <source-dir>
set -u
bin=$1
src=$2
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
fail=0
header="time_s,stage,normal_stress_MPa,shear_disp_mm,shear_stress_MPa,normal_disp_mm"

# record FILE "STAGE:SIGMA:AMPLITUDE ..." [SHIFT]: one-sided strokes 0 -> AMPLITUDE -> 0 (negative
# amplitude: the first stroke goes negative), 0.5 mm steps, a simple elastic-plastic stress.
record() {
  local file=$1 spec=$2 shift=${3:-0}
  {
    echo "# specimen: cli"
    echo "$header"
    for s in $spec; do
      IFS=: read -r st sn a <<<"$s"
      awk -v st="$st" -v sn="$sn" -v a="$a" -v sh="$shift" -v t0="$st" 'BEGIN {
        n = int((a < 0 ? -a : a) / 0.5); sg = a < 0 ? -1 : 1
        for (i = 0; i <= 2 * n; i++) {
          k = i <= n ? i : 2 * n - i; u = sg * 0.5 * k; up = i <= n ? 1 : -1
          tau = sg * up * (k < 3 ? 0.6 * k : 1.8) * sn / 3 + sh
          printf "%.3f,%d,%g,%g,%g,%g\n", 1000 * t0 + i, st, sn, u, tau, 0.01 * k
        }
      }'
    done
  } >"$file"
}

# shellcheck source=lib/expect.sh
source "$(dirname "$0")/lib/expect.sh"
# expect_compare NAME CODE ARGS... -- SUBSTRINGS...: `rockdem compare ARGS...` (lib/expect.sh).
expect_compare() {
  local name=$1 code=$2
  shift 2
  expect "$name" "$code" compare "$@"
}

record "$tmp/data.csv" "1:3:10 2:4:10"

# Broken measurement files: the reader names file:line and the rule, compare exits 2.
printf '# specimen: x\ntime_s,stage,normal_stress_MPa,shear_disp_mm,shear_stress_MPa\n0,1,3,0,0\n' >"$tmp/no_col.csv"
expect_compare missing_column 2 --data "$tmp/no_col.csv" --model "$tmp/data.csv" -- \
  "no_col.csv:2:" "missing column 'normal_disp_mm'"
{ echo "$header"; echo "0,1,3,0,0,0"; echo "1,1,3,0.5,nan,0"; } >"$tmp/nan.csv"
expect_compare nan_value 2 --data "$tmp/data.csv" --model "$tmp/nan.csv" -- "nan.csv:3:" "NaN in column 'shear_stress_MPa'"
{ echo "$header"; echo "0,1,3,0,0,0"; echo "2,1,3,0.5,0.1,0"; echo "1,1,3,1,0.2,0"; } >"$tmp/back.csv"
expect_compare time_backwards 2 --data "$tmp/back.csv" --model "$tmp/data.csv" -- "back.csv:4:" "time going backwards"
{ echo "$header"; echo "0,1,3,0,0,0"; echo "1,1,3,0.5,abc,0"; } >"$tmp/text.csv"
expect_compare non_numeric 2 --data "$tmp/text.csv" --model "$tmp/data.csv" -- "text.csv:3:" "non-numeric value 'abc'"
{ echo "$header"; echo "0,1,3,0,0,0"; echo "1,1,3,0.5,0"; } >"$tmp/short.csv"
expect_compare short_row 2 --data "$tmp/short.csv" --model "$tmp/data.csv" -- "short.csv:3:" "row has 5 fields, the header has 6"
expect_compare missing_file 2 --data "$tmp/none.csv" --model "$tmp/data.csv" -- "--data $tmp/none.csv: no such file"
echo "$header" >"$tmp/empty.csv"
expect_compare no_rows 2 --data "$tmp/empty.csv" --model "$tmp/data.csv" -- "empty.csv vs" "no data rows"

# Incompatible records: refused, saying what differs.
record "$tmp/one_stage.csv" "1:3:10"
expect_compare other_stages 2 --data "$tmp/data.csv" --model "$tmp/one_stage.csv" -- \
  "data.csv vs $tmp/one_stage.csv" "different stages" "measurement has stage(s) 1, 2, the model 1"
record "$tmp/short_stroke.csv" "1:3:10 2:4:4"
expect_compare other_amplitude 2 --data "$tmp/data.csv" --model "$tmp/short_stroke.csv" -- \
  "stage 2: different shear paths" "measurement spans +0 .. +10 mm, the model +0 .. +4 mm"
record "$tmp/negative.csv" "1:3:10 2:4:-10"
expect_compare opposite_sign 2 --data "$tmp/data.csv" --model "$tmp/negative.csv" -- \
  "stage 2: opposite first strokes" "toward the positive side, the model toward the negative side"
record "$tmp/sigma.csv" "1:3:10 2:6:10"
expect_compare other_normal_stress 2 --data "$tmp/data.csv" --model "$tmp/sigma.csv" -- \
  "stage 2: different normal stress" "the measurement 4 MPa, the model 6 MPa"
{ cat "$tmp/data.csv"; } >"$tmp/two_cycles.csv"
awk -F, 'NR > 2 && $2 == 2 { printf "%.3f,%s,%s,%s,%s,%s\n", $1 + 500, $2, $3, $4, $5, $6 }' "$tmp/data.csv" \
  >>"$tmp/two_cycles.csv"
expect_compare other_cycles 2 --data "$tmp/data.csv" --model "$tmp/two_cycles.csv" -- \
  "stage 2: different shear paths" "measurement has 1 reversal (1 cycle), the model 3 reversals (2 cycles)"

# A good pair: exit 0, the table, the JSON; a 0.2 MPa offset shows as the bias.
record "$tmp/offset.csv" "1:3:10 2:4:10" 0.2
expect_compare good_pair 0 --data "$tmp/data.csv" --model "$tmp/offset.csv" --json "$tmp/out.json" -- \
  "overall" "+0.2000" "quadrant 4" "combined NRMSE" "predicted by" "MPa in magnitude"
grep -qF '"combined"' "$tmp/out.json" && grep -qF '"segments"' "$tmp/out.json" ||
  { echo "FAIL good_pair: JSON lacks nrmse.combined or segments"; fail=1; }
expect_compare identical 0 --data "$tmp/data.csv" --model "$tmp/data.csv" -- "combined NRMSE (mean of the two): 0.0000"
# --plot through Debian's python (skipped, and said so, where it has no matplotlib).
if /usr/bin/python3 -c "import matplotlib" 2>/dev/null; then
  expect_compare plot 0 --data "$tmp/data.csv" --model "$tmp/offset.csv" --plot "$tmp/fig" --quiet --
  [ -s "$tmp/fig/offset.png" ] || { echo "FAIL plot: no $tmp/fig/offset.png"; fail=1; }
  # The folder may hold other comparisons' figures; an earlier figure of this one is replaced only
  # with --overwrite, and that is refused before anything runs.
  expect_compare plot_again 2 --data "$tmp/data.csv" --model "$tmp/offset.csv" --plot "$tmp/fig" -- \
    "--plot $tmp/fig: 'offset.png' exists" "--overwrite"
  expect_compare plot_other_model 0 --data "$tmp/data.csv" --model "$tmp/data.csv" --plot "$tmp/fig" --quiet --
  : > "$tmp/fig/offset.png"  # emptied: only a replaced figure has content again
  expect_compare plot_overwrite 0 --data "$tmp/data.csv" --model "$tmp/offset.csv" --plot "$tmp/fig" --overwrite --quiet --
  [ -s "$tmp/fig/offset.png" ] && [ -s "$tmp/fig/data.png" ] || { echo "FAIL plot_overwrite: the figure was not replaced"; fail=1; }
else
  echo "skip plot: /usr/bin/python3 has no matplotlib"
fi

expect_compare overwrite_alone 2 --data "$tmp/data.csv" --model "$tmp/offset.csv" --overwrite -- "--overwrite goes with --json, --save-model or --plot"

# The case-level form runs the element test first; compared with that test's own record: zero.
case_file="$src/cases/direct_shear/test09_mohr_coulomb.toml"
if "$bin" element "$case_file" --out "$tmp/t9.csv" >/dev/null 2>&1; then
  expect_compare case_form 0 --data "$tmp/t9.csv" --case "$case_file" --save-model "$tmp/t9_model.csv" -- \
    "combined NRMSE (mean of the two): 0.0000" "worst segments: none"
  cmp -s <(grep -v '^#' "$tmp/t9.csv") <(grep -v '^#' "$tmp/t9_model.csv") ||
    { echo "FAIL case_form: --save-model record differs from rockdem element's"; fail=1; }
else
  echo "FAIL case_form: rockdem element $case_file failed"
  fail=1
fi
expect_compare case_missing 2 --data "$tmp/data.csv" --case "$tmp/none.toml" -- "--case $tmp/none.toml: no such file"
expect_compare no_model 2 --data "$tmp/data.csv" -- "give --model FILE.csv or --case CASE.toml"
expect_compare both_models 2 --data "$tmp/data.csv" --model "$tmp/data.csv" --case "$case_file" -- "not both"
expect_compare no_data 2 --model "$tmp/data.csv" -- "--data MEASURED.csv is required"
expect_compare save_without_case 2 --data "$tmp/data.csv" --model "$tmp/data.csv" --save-model "$tmp/x.csv" -- \
  "--save-model goes with --case"
expect_compare case_other_path 2 --data "$tmp/data.csv" --case "$case_file" -- "data.csv vs $case_file" "different stages" "the model 1, 2, 3"

exit $fail
