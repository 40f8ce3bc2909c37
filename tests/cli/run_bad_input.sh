#!/usr/bin/env bash
# Bad DEM case files for `rockdem run`: each must stop before any computation with exit code 2
# and a message naming the file, the line or key, what is wrong and what is valid. An unstable run
# must stop with exit code 3 after writing its last good state.
# Usage: bash run_bad_input.sh <rockdem-binary> <source-dir>
set -u
bin=$1
src=$2
base="$src/cases/direct_shear/test09_coulomb.toml"
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
fail=0

# variant NAME PYTHON-EXPR: writes $tmp/NAME.toml from the base case, transformed by a sed script.
variant() { sed "$2" "$base" > "$tmp/$1.toml"; }

# expect NAME CODE SUBSTRING...: runs the case, wants exit CODE and every substring in the output.
expect() {
  local name=$1 want_code=$2
  shift 2
  local out code
  out=$(timeout 300 "$bin" run "$tmp/$name.toml" --out "$tmp/out_$name" --quiet 2>&1)
  code=$?
  if [ "$code" -ne "$want_code" ]; then
    echo "FAIL $name: exit $code, wanted $want_code: $out"
    fail=1
    return
  fi
  for want in "$@"; do
    if ! grep -qF -- "$want" <<<"$out"; then
      echo "FAIL $name: message lacks '$want': $out"
      fail=1
      return
    fi
  done
  echo "ok   $name ($code): $(head -c 300 <<<"$out")"
}

variant syntax 's/^rounding = "0.5 mm"/rounding = "0.5 mm/'
expect syntax 2 "syntax.toml:" "TOML syntax error"

# The two case-file dialects mixed: a DEM case with a laboratory-test table, and a laboratory-test
# case whose stages are written the DEM way ([[stages]]): both named, with an example of each.
{ cat "$base"; printf '\n[specimen]\nname = "test09"\n'; } > "$tmp/mixed.toml"
expect mixed 2 "mixed.toml: has tables of a laboratory-test case file ([specimen])" "and of a DEM case file ([blocks]" \
  "cases/direct_shear/test09_mohr_coulomb.toml" "cases/sliding_block/incline.toml"
sed 's/^\[\[stage\]\]/[[stages]]/; s/^\[stage\.params\]/[stages.params]/' "$src/cases/direct_shear/test09_mohr_coulomb.toml" |
  awk '/^\[stages\.params\]/{exit} {print}' > "$tmp/lab_stages.toml"
expect lab_stages 2 "lab_stages.toml: has tables of a laboratory-test case file" "and of a DEM case file ([stages])" \
  "a laboratory-test case has [specimen], [joint] and [[stage]]"
sed '/^\[\[stage\]\]/,$d' "$src/cases/direct_shear/test09_mohr_coulomb.toml" > "$tmp/lab_no_stage.toml"
expect lab_no_stage 2 "lab_no_stage.toml: has tables of a laboratory-test case file" "but no [[stage]] table"

variant unknown_key 's/^detection_tolerance = /detektion_tolerance = /'
expect unknown_key 2 "unknown key 'detektion_tolerance'" "valid keys:" "detection_tolerance"

variant missing_value '/^shear = "14.41 GPa"/d'
expect missing_value 2 "missing required parameter 'shear'" "rock material 'elastic'"

variant unitless 's/^kn = "35964 MPa\/m"/kn = 35964e6/'
expect unitless 2 "unitless.toml:" "'kn'" "no unit" "GPa/m"

variant negative_stiffness 's/^ks = "16929 MPa\/m"/ks = "-16929 MPa\/m"/'
expect negative_stiffness 2 "'ks'" "out of range" "valid range"

variant friction_90 's/^friction = "38 deg"/friction = "90 deg"/'
expect friction_90 2 "'friction'" "out of range" "90 deg"

variant zero_density 's/^density = "2418.8 kg\/m3"/density = "0 kg\/m3"/'
expect zero_density 2 "'density'" "out of range"

variant unknown_law 's/^law = "coulomb_slip"/law = "colomb_slip"/'
expect unknown_law 2 "unknown joint law 'colomb_slip'" "coulomb_slip" "mohr_coulomb"

variant unknown_material 's/^material = "tuff"/material = "granite"/'
expect unknown_material 2 "unknown material 'granite'" "tuff"

variant overlap 's/^rectangle = \["51 mm", "0 mm", "203 mm", "102 mm"\]/rectangle = ["51 mm", "-5 mm", "203 mm", "102 mm"]/'
expect overlap 2 "blocks 'bottom' and 'top' overlap"

# A component of a model-wide quantity: checked like any other (it used to be ignored, so every
# energy history recorded the kinetic energy), and refused on a quantity that has none.
variant energy_component '0,/^\[\[histories\]\]$/s//[[histories]]\nname = "e"\nquantity = "energy"\ncomponent = "strian"\n\n[[histories]]/'
expect energy_component 2 "unknown component 'strian'" "strain"
variant ratio_component '0,/^\[\[histories\]\]$/s//[[histories]]\nname = "r"\nquantity = "unbalanced_ratio"\ncomponent = "x"\n\n[[histories]]/'
expect ratio_component 2 "'unbalanced_ratio' has no components"

variant missing_file 's/^vx = { cycles = .*/vx = { file = { path = "no_such_history.txt", value_unit = "mm\/s" } }/'
expect missing_file 2 "no_such_history.txt" "does not exist"

variant bad_unit 's/^normal = "3 MPa"/normal = "3 mm"/'
expect bad_unit 2 "unit 'mm' is a length" "stress"

variant bad_stage 's/^stages = \["shear"\]/stages = ["shearing"]/'
expect bad_stage 2 "stage 'shearing'" "consolidate, shear"

expect_missing_case() {
  local out code
  out=$("$bin" run "$tmp/does_not_exist.toml" 2>&1)
  code=$?
  if [ "$code" -ne 2 ] || ! grep -qF "does not exist" <<<"$out"; then echo "FAIL missing case: $code $out"; fail=1; else echo "ok   missing case file"; fi
}
expect_missing_case

# A fixed time step 100 times the critical one is refused before the stage runs, with the
# stable step.
variant dt_too_large 's/^refresh_interval = 10 .*/refresh_interval = 10\nfixed_dt = "1e-4 s"/'
expect dt_too_large 2 "fixed_dt" "above the stable time step" "give at most"

# A side that vanishes against its corner's coordinate (found by the parser replay, tests/fuzz/:
# the model's check said "block 'upper': outline is not a simple polygon" without file or key).
variant vanishing_side 's/^rectangle = \["51 mm", "0 mm", "203 mm", "102 mm"\]/rectangle = ["1e308 mm", "0 mm", "203 mm", "102 mm"]/'
expect vanishing_side 2 "vanishing_side.toml:51" "rectangle" "corners coincide in double precision"

# Unstable: a velocity limit below the loading block's 100 mm/s stands in for a run that blows up.
# The run must stop, name the step and the block, and leave the last good state behind.
variant unstable 's/^refresh_interval = 10 .*/refresh_interval = 10\nvelocity_limit = "1 mm\/s"/'
expect unstable 3 "at step" "of block" "last good state"
if [ -f "$tmp/out_unstable/last_good_state.h5" ]; then echo "ok   last good state written"; else echo "FAIL no last_good_state.h5"; fail=1; fi

exit $fail
