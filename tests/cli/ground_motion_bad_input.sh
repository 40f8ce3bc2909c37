#!/usr/bin/env bash
# `rockdem ground-motion` on bad records and bad options: each must exit 2 with a message naming
# the file:line or the option, what is wrong and what is valid. Two good runs check that the
# drive file has the columns the case readers expect and that the SDOF check values print.
# Usage: bash ground_motion_bad_input.sh <rockdem-binary> <source-dir>
set -u
bin=$1
src=$2
mx="$src/cases/data/ground_motions/mexico1985_sct_acc_g.txt"
ec="$src/cases/data/ground_motions/elcentro1940_ns_acc_g.csv"
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
fail=0

# expect NAME CODE 'SUBSTRING...' -- ARGS...: runs ground-motion ARGS, wants exit CODE and every substring.
expect() {
  local name=$1 want_code=$2
  shift 2
  local wants=()
  while [ "$1" != "--" ]; do wants+=("$1"); shift; done
  shift
  local out code
  out=$("$bin" ground-motion "$@" 2>&1)
  code=$?
  if [ "$code" -ne "$want_code" ]; then
    echo "FAIL $name: exit $code, wanted $want_code: $out"
    fail=1
    return
  fi
  for want in "${wants[@]}"; do
    if ! grep -qF -- "$want" <<<"$out"; then
      echo "FAIL $name: output lacks '$want': $out"
      fail=1
      return
    fi
  done
  echo "ok   $name: $(tail -n 1 <<<"$out")"
}

expect no_record 2 "no record given" -- --units g
expect no_units 2 "--units is required" "g, m/s^2" -- "$mx" --column 3
expect bad_units 2 "option --units" "acceleration unit 'mm'" "m/s2, g" -- "$mx" --column 3 --units mm
expect missing_file 2 "nowhere.txt" "no such file" -- "$tmp/nowhere.txt" --units g
expect no_column 2 "mexico1985_sct_acc_g.txt:1" "column 7 does not exist" "valid: a column number 1..4" -- \
  "$mx" --column 7 --units g
expect no_named_column 2 "elcentro1940_ns_acc_g.csv:1" "no column named 'ns'" "'acc (g)'" -- "$ec" --column ns --units g
expect unitless_corner 2 "option --highpass '0.2'" "Hz" -- "$mx" --column 3 --units g --highpass 0.2 --out "$tmp/d.csv"
expect swapped_corners 2 "high-pass corner 2 Hz must be below the low-pass corner 0.2 Hz" -- \
  "$mx" --column 3 --units g --highpass "2 Hz" --lowpass "0.2 Hz" --out "$tmp/d.csv"
expect corner_above_nyquist 2 "valid corners are in [0, 25 Hz)" -- "$mx" --column 3 --units g --lowpass "30 Hz" --peak "1 mm"
expect window_outside 2 "outside the record" "0.02 s to 163.42 s" -- "$mx" --column 3 --units g --start "150 s" --end "200 s" \
  --out "$tmp/d.csv"
expect window_reversed 2 "end 40 s must be after start 80 s" -- "$mx" --column 3 --units g --start "80 s" --end "40 s" \
  --out "$tmp/d.csv"
expect bad_order 2 "option --order '0'" "valid: an integer from 1 to 8" -- "$mx" --column 3 --units g --order 0 --peak "1 mm"
expect bad_disp_baseline 2 "displacement baseline degree 1" "2..10" -- "$mx" --column 3 --units g --disp-baseline-degree 1 \
  --peak "1 mm"
expect long_taper 2 "taper of 30 s" "at most half its length" -- "$mx" --column 3 --units g --start "40 s" --end "80 s" \
  --taper "30 s" --peak "1 mm"
expect bad_peak 2 "option --peak '25.4'" "m, cm, mm" -- "$mx" --column 3 --units g --peak 25.4
expect unknown_option 2 "unknown arguments '--bogus'" "--help" -- "$mx" --column 3 --units g --bogus
expect bad_period 2 "option --sdof-periods 'x'" -- "$ec" --units g --sdof-periods 0.5,x
expect bad_damping 2 "damping ratio 1.5" "0 <= damping < 1" -- "$ec" --units g --sdof-periods 1 --damping 1.5
expect dt_with_time_column 2 "option --dt is only for records without a time column" -- "$ec" --units g --dt "0.01 s"
# A write failure is not an input error: exit 1 naming the path (docs/reliability.md).
expect out_folder_missing 2 "--out $tmp/no/dir/d.csv" "does not exist" -- "$mx" --column 3 --units g --peak "1 mm" --out "$tmp/no/dir/d.csv"

printf '0 0.1\n0.02 0.2\n0.05 0.1\n0.06 0.0\n' >"$tmp/uneven.txt"
expect uneven_record 2 "uneven.txt:3" "off the uniform grid" "resample" -- "$tmp/uneven.txt" --units g
printf '0 0.1\n0.02 zz\n' >"$tmp/text.txt"
expect text_in_record 2 "text.txt:2" "column 2 holds 'zz'" "not a finite number" -- "$tmp/text.txt" --units g

# Good runs.
expect sdof_check 0 "0.067940" "0.151592" "0.189675" -- "$ec" --units "9.81 m/s^2" --sdof-periods 0.5,1,2 --damping 0.02
expect drive 0 "peak" "-> $tmp/drive.csv" -- "$mx" --column 3 --units g --start "40 s" --end "80 s" --taper "3 s" \
  --pad "10 s" --highpass "0.2 Hz" --lowpass "2 Hz" --peak "25.4 mm" --out "$tmp/drive.csv"
if [ -f "$tmp/drive.csv" ]; then
  header=$(grep -v '^#' "$tmp/drive.csv" | head -n 1)
  if [ "$header" != "time_s,shear_disp_mm" ]; then echo "FAIL drive header: '$header'"; fail=1; fi
  for key in "# drive:" "# processing:" "# source: $mx"; do
    grep -qF -- "$key" "$tmp/drive.csv" || { echo "FAIL drive metadata lacks '$key'"; fail=1; }
  done
fi

if [ "$fail" -ne 0 ]; then
  echo "ground-motion bad-input checks FAILED"
  exit 1
fi
echo "ground-motion bad-input checks passed"
