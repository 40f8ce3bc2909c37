#!/usr/bin/env bash
# Every case in cases/element runs and writes a measurement CSV; `rockdem laws` and
# `rockdem describe` list what the registries hold.
# Usage: bash element_cases.sh <rockdem-binary> <source-dir>
set -u
bin=$1
src=$2
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
fail=0
header="time_s,stage,normal_stress_MPa,shear_disp_mm,shear_stress_MPa,normal_disp_mm"
for case in "$src"/cases/element/*.toml; do
  name=$(basename "$case" .toml)
  if ! out=$("$bin" element "$case" --out "$tmp/$name.csv" 2>&1); then
    echo "FAIL $name: $out"
    fail=1
    continue
  fi
  grep -q "^$header" "$tmp/$name.csv" || { echo "FAIL $name: no measurement header"; fail=1; }
  if grep -q "warning" <<<"$out"; then
    echo "FAIL $name: $out"
    fail=1
  fi
  echo "ok   $out"
done
# Figure 3-2's plateau (3 tan 38 deg = 2.3439 MPa both ways) appears in the summary.
"$bin" element "$src/cases/element/report_fig3-2_mohr_coulomb.toml" --out "$tmp/f.csv" |
  grep -qF -- "-2.3439 .. +2.3439 MPa" || { echo "FAIL fig 3-2 plateau"; fail=1; }
# Default output name: <case stem>.csv in the current folder; the loop above wrote it already, so
# it is refused (exit 2) and left as it was unless --overwrite.
rm -rf "$tmp/default" && mkdir "$tmp/default"
(cd "$tmp/default" && "$bin" element --quiet "$src/cases/element/report_fig3-5_barton_bandis.toml") &&
  [ -s "$tmp/default/report_fig3-5_barton_bandis.csv" ] || { echo "FAIL default output name"; fail=1; }
echo "an earlier result" > "$tmp/default/report_fig3-5_barton_bandis.csv"
out=$(cd "$tmp/default" && "$bin" element --quiet "$src/cases/element/report_fig3-5_barton_bandis.toml" 2>&1)
code=$?
{ [ $code -eq 2 ] && grep -qF "the default --out report_fig3-5_barton_bandis.csv: the file exists" <<<"$out" &&
  grep -qx "an earlier result" "$tmp/default/report_fig3-5_barton_bandis.csv"; } ||
  { echo "FAIL default output name again: exit $code, $out"; fail=1; }
(cd "$tmp/default" && "$bin" element --quiet --overwrite "$src/cases/element/report_fig3-5_barton_bandis.toml") &&
  grep -q "^$header" "$tmp/default/report_fig3-5_barton_bandis.csv" || { echo "FAIL --overwrite did not replace"; fail=1; }
# path = "file": replay the shear displacement history of stage 2 of a measurement file.
cat >"$tmp/record.csv" <<CSV
# specimen: replay
time_s,stage,normal_stress_MPa,shear_disp_mm,shear_stress_MPa,normal_disp_mm
0,1,1,0,0,0
5,1,1,1,0,0
10,2,2,0,0,0
20,2,2,3,0,0
30,2,2,-2,0,0
CSV
cat >"$tmp/replay.toml" <<CASE
[joint]
law = "mohr_coulomb"
[joint.params]
kn = "36 GPa/m"
ks = "17 GPa/m"
friction = "38 deg"
[[stage]]
normal_stress = "2 MPa"
path = "file"
file = "record.csv"
file_stage = 2
CASE
if out=$("$bin" element "$tmp/replay.toml" --out "$tmp/replay.csv" 2>&1); then
  last=$(tail -n 1 "$tmp/replay.csv")
  case "$last" in
    20,1,*,-2,*) echo "ok   replay: $last" ;;
    *) echo "FAIL replay: last row '$last' should be at t = 20 s (stage times from 0), u = -2 mm"; fail=1 ;;
  esac
else
  echo "FAIL replay: $out"
  fail=1
fi
out=$("$bin" laws)
for n in mohr_coulomb barton_bandis continuously_yielding coulomb_slip strength_reduction; do
  grep -qF "$n" <<<"$out" || { echo "FAIL laws lacks $n"; fail=1; }
done
out=$("$bin" describe barton_bandis)
for w in "jrc" "residual_friction" "lab_length" "Table 4-3" "default:" "allowed:" "udec_legacy"; do
  grep -qF -- "$w" <<<"$out" || { echo "FAIL describe barton_bandis lacks $w"; fail=1; }
done
"$bin" describe strength_reduction | grep -qF "enabled" || { echo "FAIL describe strength_reduction"; fail=1; }
exit $fail
