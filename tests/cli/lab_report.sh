#!/usr/bin/env bash
# scripts/lab-report on a small fixture: test 9 with two laws against a made-up twin (the
# Mohr-Coulomb record with its shear stress scaled by 1.1), and test 7 without a twin. The page
# must hold the NRMSE table, both figures and the worst-segment lines, and name the missing twin;
# the exit code must be 1 because of it.
# Usage: bash lab_report.sh <rockdem-binary> <source-dir>
set -u
bin=$1
src=$2
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
fail=0
if ! /usr/bin/python3 -c "import matplotlib" 2>/dev/null; then
  echo "skip: /usr/bin/python3 has no matplotlib (python3-matplotlib), which the lab report needs"
  exit 0
fi
mkdir -p "$tmp/cases/twins"
for c in test09_mohr_coulomb test09_barton_bandis test07_mohr_coulomb; do
  cp "$src/cases/direct_shear/$c.toml" "$tmp/cases/" || { echo "FAIL: no case $c"; exit 1; }
done
"$bin" element "$tmp/cases/test09_mohr_coulomb.toml" --out "$tmp/base.csv" --quiet || { echo "FAIL: element"; exit 1; }
awk -F, 'BEGIN { OFS = "," } /^#/ || /^time_s/ { print; next } { $5 = $5 * 1.1; print }' "$tmp/base.csv" \
  >"$tmp/cases/twins/test09.csv"

out=$(ROCKDEM_BIN=$bin bash "$src/scripts/lab-report" --out "$tmp/rep" --cases "$tmp/cases" --tests "09 07" \
  --laws "mohr_coulomb barton_bandis" 2>&1)
code=$?
echo "$out"
[ "$code" -eq 1 ] || { echo "FAIL: exit $code, wanted 1 (a twin is missing)"; fail=1; }
page="$tmp/rep/index.html"
[ -s "$page" ] || { echo "FAIL: no $page"; exit 1; }
for want in "NRMSE by test, law and quadrant" "test 07, mohr_coulomb: measurement twin missing" \
  "test 07, barton_bandis: case file missing" "figures/test09_mohr_coulomb.png" "figures/test09_barton_bandis.png" \
  "reverse shearing (quadrant 4)" "2 comparison(s) made, 2 failed or missing"; do
  grep -qF -- "$want" "$page" || { echo "FAIL: page lacks '$want'"; fail=1; }
done
for f in figures/test09_mohr_coulomb.png figures/test09_barton_bandis.png json/test09_mohr_coulomb.json; do
  [ -s "$tmp/rep/$f" ] || { echo "FAIL: no $f"; fail=1; }
done
# The 10 % stress scaling shows: Mohr-Coulomb against its own record scaled is under-predicted.
grep -qF "under-predicted" "$tmp/rep/json/test09_mohr_coulomb.json" ||
  { echo "FAIL: the scaled twin does not show as under-prediction"; fail=1; }
[ $fail -eq 0 ] && echo "ok   lab-report fixture"
exit $fail
