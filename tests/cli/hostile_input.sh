#!/usr/bin/env bash
# Hostile input and the command-line contract (docs/reliability.md): values that overflow on unit
# conversion, NaN/inf from expressions, absurd sizes, tiny time steps in ground-motion
# processing, mistyped subcommands, options and keys, and results that would hold nan/inf. Each
# must end with the contract's exit code (0, 1, 2, 3) and a message naming the file, key, option
# or path; none may crash, hang or write a non-finite result.
# Usage: bash hostile_input.sh <rockdem-binary> <source-dir>
set -u
bin=$1
src=$2
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
fail=0
. "$src/tests/cli/lib/expect.sh"
incline="$src/cases/sliding_block/incline.toml"
lab="$src/cases/direct_shear/test09_mohr_coulomb.toml"
# variant NAME BASE SED-SCRIPT: $tmp/NAME.toml from BASE transformed by sed.
variant() { sed "$3" "$2" > "$tmp/$1.toml"; }
# Every command below is bounded: a hang is a failure, not a stuck test.
run() { timeout 120 "$bin" "$@"; }

# --- 2. the command-line contract -------------------------------------------------------------
expect no_subcommand 2 -- "a subcommand is required" "Usage"
expect help 0 help -- "Subcommands" "run"
expect help_run 0 help run -- "--out"
expect typo_subcommand 2 runn x.toml -- "unknown subcommand 'runn' (did you mean 'run'?)"
expect typo_option 2 run "$incline" --ovewrite -- "unknown option '--ovewrite' (did you mean '--overwrite'?)" "Usage"
expect version 0 --version -- "rockdem"
variant law_typo "$incline" 's/law = "coulomb_slip"/law = "coulomb_slipp"/'
expect law_typo 2 run "$tmp/law_typo.toml" --out "$tmp/o_law" --quiet -- "law_typo.toml" "did you mean 'coulomb_slip'?"
variant key_typo "$incline" 's/^rounding = /roundin = /'
expect key_typo 2 run "$tmp/key_typo.toml" --out "$tmp/o_key" --quiet -- "key_typo.toml:" "unknown key 'roundin'" "did you mean 'rounding'?"
expect describe_typo 2 describe coulomb_slp -- "unknown name 'coulomb_slp' (did you mean 'coulomb_slip'?)"
variant lab_syntax "$lab" 's/^law = "mohr_coulomb"/law = "mohr_coulomb/'
expect lab_syntax_write_case 2 run "$tmp/lab_syntax.toml" --write-case "$tmp/w.toml" -- "lab_syntax.toml:" "TOML syntax error"
expect dem_case_to_element 2 element "$incline" --out "$tmp/e.csv" -- "incline.toml" "is a DEM case file" "rockdem run"

# --- 1b. values that overflow on conversion, nonsense tolerances --------------------------------
variant kn_overflow "$incline" 's/^kn = "10 GPa\/m"/kn = "1e308 GPa\/m"/'
expect kn_overflow 2 run "$tmp/kn_overflow.toml" --out "$tmp/o1" --quiet -- "kn_overflow.toml:" "kn" "overflows"
variant gravity_overflow "$incline" 's/^gravity = .*/gravity = ["1e308 g", "0 g"]/'
expect gravity_overflow 2 run "$tmp/gravity_overflow.toml" --out "$tmp/o2" --quiet -- "gravity" "overflows"
variant huge_block "$incline" 's/rectangle = \["0 m", "0 m", "1 m", "0.5 m"\]/rectangle = ["0 m", "0 m", "1e308 km", "0.5 m"]/'
expect huge_block 2 run "$tmp/huge_block.toml" --out "$tmp/o3" --quiet -- "huge_block.toml:" "overflows"
variant neg_tolerance "$incline" 's/^detection_tolerance = "1 mm"/detection_tolerance = "-1 mm"/'
expect neg_tolerance 2 run "$tmp/neg_tolerance.toml" --out "$tmp/o4" --quiet -- "detection_tolerance" "must not be negative"
variant lab_kn_overflow "$lab" 's/^kn = "35.964 GPa\/m"/kn = "1e308 GPa\/m"/'
expect lab_kn_overflow 2 element "$tmp/lab_kn_overflow.toml" --out "$tmp/kn.csv" -- "lab_kn_overflow.toml:" "overflows"
variant tiny_step "$lab" 's/^step = "0.01 mm"/step = "1e-5 mm"/'
expect tiny_step 2 element "$tmp/tiny_step.toml" --out "$tmp/ts.csv" -- "tiny_step.toml" "at most 1e7 increments" "[element] step"
variant huge_amplitude "$lab" 's/^amplitude = "40 mm"/amplitude = "2147483648 mm"/'
expect huge_amplitude 2 element "$tmp/huge_amplitude.toml" --out "$tmp/ha.csv" -- "huge_amplitude.toml" "at most 1e7 increments"
[ -e "$tmp/kn.csv" ] || [ -e "$tmp/ts.csv" ] || [ -e "$tmp/ha.csv" ] && { echo "FAIL a refused element run left a CSV"; fail=1; }

# --- 1c. NaN/inf from a time-function expression ----------------------------------------------
variant expr_nan "$incline" 's/^vx = "0 m\/s"/vx = { expression = { value = "sqrt(-1)", unit = "m\/s" } }/'
expect expr_nan 2 run "$tmp/expr_nan.toml" --out "$tmp/o5" --quiet -- "expr_nan.toml" "sqrt(-1)" "not a number"
variant expr_inf "$incline" 's/^vx = "0 m\/s"/vx = { expression = { value = "1\/0", unit = "m\/s" } }/'
expect expr_inf 2 run "$tmp/expr_inf.toml" --out "$tmp/o6" --quiet -- "expr_inf.toml" "infinite"
# Finite at t = 0, NaN from t = 0.001 s on: only the engine's per-step check can catch it.
variant expr_late_nan "$incline" 's/^vx = "0 m\/s"/vx = { expression = { value = "sqrt(0.001-t)", unit = "m\/s" } }/'
expect expr_late_nan 3 run "$tmp/expr_late_nan.toml" --out "$tmp/o7" --quiet -- "non-finite" "last good state"
[ -f "$tmp/o7/last_good_state.h5" ] || { echo "FAIL expr_late_nan: no last_good_state.h5"; fail=1; }

# --- 1a. ground-motion with a tiny time step ----------------------------------------------------
printf '0.1\n0.2\n-0.1\n0.05\n0.0\n-0.2\n0.1\n0.0\n' > "$tmp/acc.txt"
expect taper_tiny_dt 2 ground-motion "$tmp/acc.txt" --time-column 0 --column 1 --units g --dt "1e-300 s" --taper "2 s" --out "$tmp/d.csv" -- \
  "--taper" "at most 1e9 samples"
expect pad_tiny_dt 2 ground-motion "$tmp/acc.txt" --time-column 0 --column 1 --units g --dt "1e-300 s" --pad "2 s" --out "$tmp/d.csv" -- \
  "--pad" "at most 1e9 samples"
printf '0.1\n1e308\n-0.1\n0.05\n0.0\n-0.2\n0.1\n0.0\n' > "$tmp/acc_big.txt"
expect ground_motion_overflow 2 ground-motion "$tmp/acc_big.txt" --time-column 0 --column 1 --units g --dt "0.01 s" --out "$tmp/d2.csv" -- \
  "acc_big.txt" "not finite"
[ -e "$tmp/d2.csv" ] && { echo "FAIL ground_motion_overflow wrote $tmp/d2.csv"; fail=1; }

# --- 1e. compare never reports nan/inf; metadata read as numbers is checked ---------------------
twin="$src/cases/direct_shear/twins/test09.csv"
sed '0,/^[0-9]/{s/^\([0-9][^,]*\),\([^,]*\),\([^,]*\),\([^,]*\),\([^,]*\),/\1,\2,\3,\4,1e308,/}' "$twin" > "$tmp/big.csv"
expect compare_overflow 2 compare --data "$tmp/big.csv" --model "$twin" --json "$tmp/c.json" -- "big.csv" "not finite"
[ -e "$tmp/c.json" ] && { echo "FAIL compare_overflow wrote $tmp/c.json"; fail=1; }
sed 's/^# joint_length_m:.*/# joint_length_m: abc/' "$twin" > "$tmp/len.csv"
grep -q '^# joint_length_m: abc' "$tmp/len.csv" || sed -i '1i # joint_length_m: abc' "$tmp/len.csv"
expect bad_metadata 2 compare --data "$tmp/len.csv" --model "$twin" -- "len.csv" "joint_length_m" "positive number of metres"

exit $fail
