#!/usr/bin/env bash
# Bad element case files: each must fail with a non-zero exit and a message that names the
# file and line (or key), what is wrong and what is valid.
# Usage: bash element_bad_input.sh <rockdem-binary> <source-dir>
set -u
bin=$1
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
fail=0

# check NAME EXPECTED-SUBSTRING...: runs $tmp/NAME.toml, wants exit 2 (bad input) and every substring.
check() {
  local name=$1
  shift
  local out code
  out=$("$bin" element "$tmp/$name.toml" --out "$tmp/$name.csv" 2>&1)
  code=$?
  if [ "$code" -ne 2 ]; then
    echo "FAIL $name: exit $code for a bad case, wanted 2: $out"
    fail=1
    return
  fi
  for want in "$@"; do
    if ! grep -qF -- "$want" <<<"$out"; then
      echo "FAIL $name: message lacks '$want': $out"
      fail=1
    fi
  done
  echo "ok   $name: $out"
}

params='kn = "35.964 GPa/m"
ks = "16.93 GPa/m"
friction = "38 deg"'
stage='[[stage]]
normal_stress = "3 MPa"
path = "cycles"
amplitude = "1 mm"'

cat >"$tmp/unknown_law.toml" <<CASE
[joint]
law = "mohr_colomb"
[joint.params]
$params
$stage
CASE
check unknown_law "unknown_law.toml:2" "unknown joint law 'mohr_colomb'" "valid names:" "barton_bandis" \
  "continuously_yielding" "mohr_coulomb"

cat >"$tmp/out_of_range.toml" <<CASE
[joint]
law = "mohr_coulomb"
[joint.params]
kn = "35.964 GPa/m"
ks = "16.93 GPa/m"
friction = "95 deg"
$stage
CASE
check out_of_range "out_of_range.toml:6" "'friction'" "out of range" "valid range is [0 deg, 90 deg)"

cat >"$tmp/no_unit.toml" <<CASE
[joint]
law = "mohr_coulomb"
[joint.params]
kn = "35.964 GPa/m"
ks = 16.93e9
friction = "38 deg"
$stage
CASE
check no_unit "no_unit.toml:5" "'ks'" "has no unit" "GPa/m"

cat >"$tmp/unknown_param.toml" <<CASE
[joint]
law = "barton_bandis"
[joint.params]
jrco = 7.0
CASE
check unknown_param "unknown_param.toml:4" "unknown parameter 'jrco'" "valid parameters:" "jrc" "residual_friction"

cat >"$tmp/unknown_effect.toml" <<CASE
[joint]
law = "mohr_coulomb"
effects = ["strength_reductoin"]
[joint.params]
$params
$stage
CASE
check unknown_effect "unknown_effect.toml:3" "unknown effect 'strength_reductoin'" "valid names:" "strength_reduction"

cat >"$tmp/effect_range.toml" <<CASE
[joint]
law = "mohr_coulomb"
effects = [{ name = "strength_reduction", factor = 0 }]
[joint.params]
$params
$stage
CASE
check effect_range "effect_range.toml:3" "'factor'" "valid range is [0.001, 1000]"

cat >"$tmp/stage_key.toml" <<CASE
[joint]
law = "mohr_coulomb"
[joint.params]
$params
[[stage]]
normal_stress = "3 MPa"
path = "cycles"
amplitude = "1 mm"
amplitdue = "2 mm"
CASE
check stage_key "stage_key.toml:11" "unknown key 'amplitdue'" "valid keys:" "amplitude"

cat >"$tmp/bad_path.toml" <<CASE
[joint]
law = "mohr_coulomb"
[joint.params]
$params
[[stage]]
normal_stress = "3 MPa"
path = "zigzag"
CASE
check bad_path "bad_path.toml:9" "one of {cycles, sinusoid, file}" "zigzag"

cat >"$tmp/sinusoid_without_frequency.toml" <<CASE
[joint]
law = "mohr_coulomb"
[joint.params]
$params
[[stage]]
normal_stress = "3 MPa"
path = "sinusoid"
amplitude = "5 mm"
CASE
check sinusoid_without_frequency "sinusoid_without_frequency.toml:7" "needs frequency"

cat >"$tmp/missing_path_file.toml" <<CASE
[joint]
law = "mohr_coulomb"
[joint.params]
$params
[[stage]]
normal_stress = "3 MPa"
path = "file"
file = "no_such_record.csv"
CASE
check missing_path_file "missing_path_file.toml:10" "no_such_record.csv" "not found"

cat >"$tmp/syntax.toml" <<CASE
[joint]
law = "mohr_coulomb
CASE
check syntax "syntax.toml:2" "TOML syntax error"

cat >"$tmp/no_stage.toml" <<CASE
[joint]
law = "mohr_coulomb"
[joint.params]
$params
CASE
check no_stage "no_stage.toml" "[[stage]]"

cat >"$tmp/wrong_unit.toml" <<CASE
[joint]
law = "mohr_coulomb"
[joint.params]
$params
[[stage]]
normal_stress = "3 mm"
path = "cycles"
amplitude = "1 mm"
CASE
check wrong_unit "wrong_unit.toml:8" "normal_stress" "MPa"

cat >"$tmp/bb_closure.toml" <<CASE
[joint]
law = "barton_bandis"
[joint.params]
kn = "36 GPa/m"
ks = "17 GPa/m"
jrc = 7
jcs = "170 MPa"
residual_friction = "28 deg"
lab_length = "0.2 m"
normal_closure = "bandis"
$stage
CASE
check bb_closure "bb_closure.toml:3 [joint.params]" "ucs (sigma_c) is not given" "initial_normal_stiffness"

# Missing case file.
out=$("$bin" element "$tmp/does_not_exist.toml" 2>&1)
if [ $? -ne 2 ] || ! grep -qF "does_not_exist.toml: case file not found" <<<"$out"; then
  echo "FAIL missing file: $out"
  fail=1
else
  echo "ok   missing file: $out"
fi

# describe with an unknown name lists the valid ones and exits non-zero.
out=$("$bin" describe mohr_colomb 2>&1)
if [ $? -ne 2 ] || ! grep -qF "unknown name 'mohr_colomb'" <<<"$out" || ! grep -qF "mohr_coulomb" <<<"$out"; then
  echo "FAIL describe unknown: $out"
  fail=1
else
  echo "ok   describe unknown: $out"
fi

exit $fail
