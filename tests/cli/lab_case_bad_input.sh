#!/usr/bin/env bash
# Laboratory-test case files run on their DEM specimen (`rockdem run LAB.toml`): mistakes that
# only the DEM run can see (no rock matrix, a drive it cannot follow, options for other kinds of
# case) fail with exit code 2 and a message naming the file or option, what is wrong and what is
# valid; --write-case writes a DEM case that `rockdem run` accepts as it is.
# Usage: bash lab_case_bad_input.sh <rockdem-binary> <source-dir>
set -u
bin=$1
src=$2
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
fail=0

# shellcheck source=lib/expect.sh
source "$(dirname "$0")/lib/expect.sh"

lab="$src/cases/direct_shear/test09_mohr_coulomb.toml"

# No rock matrix in [specimen]: the element test runs, the DEM run says what to add.
grep -v -E '^(density|bulk|shear) = ' "$lab" >"$tmp/norock.toml"
expect lab1 2 run "$tmp/norock.toml" --out "$tmp/o1" -- "norock.toml" "density, bulk and shear" "Table 4-1"
if ! "$bin" element "$tmp/norock.toml" --out "$tmp/norock.csv" --quiet; then
  echo "FAIL element run of a case without rock matrix"
  fail=1
fi

# Half a rock matrix.
grep -v -E '^bulk = ' "$lab" >"$tmp/halfrock.toml"
expect lab2 2 element "$tmp/halfrock.toml" --out "$tmp/h.csv" -- "halfrock.toml" "[specimen]" "all of density, bulk and shear"

# A [dem] key that does not exist, and one out of range.
sed 's/^zone_size = .*/zone_size = "20 mm"\nzones = 3/' "$lab" >"$tmp/badkey.toml"
expect lab3 2 run "$tmp/badkey.toml" --out "$tmp/o2" -- "badkey.toml" "zones" "zone_size"
sed 's/^dt_safety = .*/dt_safety = 1.5/' "$lab" >"$tmp/safety.toml"
expect lab4 2 run "$tmp/safety.toml" --out "$tmp/o3" -- "safety.toml" "dt_safety"
sed 's/^detection_tolerance = .*/detection_tolerance = "60 mm"/' "$lab" >"$tmp/tol.toml"
expect lab5 2 run "$tmp/tol.toml" --out "$tmp/o4" -- "tol.toml" "detection_tolerance" "out of range"

# Constant normal stiffness: element only.
sed '0,/^normal_stress = "3 MPa"/s//normal_stress = "3 MPa"\nnormal_control = "stiffness"\nnormal_stiffness = "1 GPa\/m"/' "$lab" >"$tmp/cns.toml"
expect lab6 2 run "$tmp/cns.toml" --out "$tmp/o5" -- "cns.toml" "constant normal stiffness" "rockdem element"

# A drive taken from one stage of a measurement record cannot drive the DEM loading block.
"$bin" element "$lab" --out "$tmp/rec.csv" --quiet
cat >"$tmp/stagefile.toml" <<CASE
[specimen]
name = "x"
joint_length = "203.2 mm"
density = "2418.8 kg/m3"
bulk = "20.96 GPa"
shear = "14.41 GPa"
[joint]
law = "coulomb_slip"
[joint.params]
kn = "36 GPa/m"
ks = "17 GPa/m"
friction = "38 deg"
[[stage]]
normal_stress = "3 MPa"
path = "file"
file = "rec.csv"
file_stage = 2
CASE
expect lab7 2 run "$tmp/stagefile.toml" --out "$tmp/o6" -- "drive file only as a whole" "time_s, shear_disp_mm"

# Options that belong to laboratory-test cases, on an ordinary DEM case; bad option values.
expect lab8 2 run "$src/cases/direct_shear/test09_coulomb.toml" --shear-velocity "1 mm/s" --out "$tmp/o7" -- "--shear-velocity" "laboratory-test"
expect lab9 2 run "$lab" --shear-velocity "3 MPa" --out "$tmp/o8" -- "--shear-velocity" "velocity"
expect lab10 2 run "$lab" --mass-scaling-dt "fast" --out "$tmp/o9" -- "--mass-scaling-dt"

# --write-case: the generated DEM case is an ordinary case file that checks and loads.
if ! "$bin" run "$lab" --write-case "$tmp/dem.toml" --quiet || ! grep -q 'shear_stages' "$tmp/dem.toml"; then
  echo "FAIL --write-case did not write the DEM case"
  fail=1
else
  # The written case must load: give it an unknown extra key to stop before running, and check
  # that the reader complains about that key only.
  printf '\n[bogus]\nx = 1\n' >>"$tmp/dem.toml"
  expect lab11 2 run "$tmp/dem.toml" --out "$tmp/o10" -- "bogus"
fi
exit $fail
