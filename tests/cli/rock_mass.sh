#!/usr/bin/env bash
# `rockdem run` on a [rock_mass] case (tests/cli/rock_mass/sample.toml): --write-blocks builds the
# model and writes the blocks for inspection without running; the case runs; and bad [rock_mass]
# input stops before running with exit code 2 and a message naming the file, the key or entry,
# what is wrong and what is valid.
# Usage: bash rock_mass.sh <rockdem-binary> <source-dir>
set -u
bin=$1
src=$2
base="$src/tests/cli/rock_mass/sample.toml"
source "$src/tests/cli/lib/expect.sh"
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
fail=0

out=$("$bin" run "$base" --write-blocks "$tmp/blocks" 2>&1)
code=$?
rows=$(($(wc -l < "$tmp/blocks/blocks.csv" 2>/dev/null || echo 0) - 1))
if [ "$code" -ne 0 ] || [ ! -s "$tmp/blocks/blocks.vtu" ] || [ ! -s "$tmp/blocks/traces.vtu" ] || [ "$rows" -lt 30 ] \
   || [ -e "$tmp/blocks/history.h5" ]; then
  echo "FAIL write-blocks: exit $code, $rows block rows: $out"
  fail=1
else
  echo "ok   write-blocks: $out"
fi
if ! grep -q "^[0-9]*,drift,drift,1,-1,0," "$tmp/blocks/blocks.csv"; then
  echo "FAIL write-blocks: no row for the opening block 'drift' (group drift, opening 0)"
  fail=1
fi

out=$("$bin" run "$base" --out "$tmp/run" --quiet 2>&1)
code=$?
if [ "$code" -ne 0 ] || ! ls "$tmp/run/vtk/" | grep -q contacts; then
  echo "FAIL run: exit $code: $out"
  fail=1
else
  echo "ok   run"
fi

# variant NAME SED-SCRIPT: writes $tmp/NAME.toml from the sample, transformed.
variant() { sed "$2" "$base" > "$tmp/$1.toml"; }

# bad NAME SUBSTRING...: the variant stops with exit 2 and every substring in the message.
bad() {
  local name=$1
  shift
  expect "$name" 2 run "$tmp/$name.toml" --out "$tmp/out_$name" --quiet -- "$@"
}

variant zero_spacing 's/^spacing = "1.5 m"/spacing = "0 m"/'
bad zero_spacing "zero_spacing.toml:" "rock_mass.joint_sets.spacing" "must be > 0"

variant dip_no_unit 's/^dip = "70 deg"/dip = 70/'
bad dip_no_unit "dip_no_unit.toml:" "rock_mass.joint_sets.dip" "no unit" "deg"

variant opening_outside 's/^centre = \["5 m", "5 m"\]/centre = ["9.5 m", "5 m"]/'
bad opening_outside "opening_outside.toml:" "[rock_mass.openings] 'drift'" "is not inside the domain"

variant region_outside 's/^rectangle = \["0 m", "8.5 m", "10 m", "1.5 m"\]/rectangle = ["20 m", "20 m", "1 m", "1 m"]/'
bad region_outside "region_outside.toml:" "[rock_mass.regions] 'far_field'" "lies outside the domain"

variant set_cuts_nothing 's/^origin = \["0.3 m", "0 m"\]/origin = ["0.3 m", "0 m"]\nregion = { rectangle = ["30 m", "30 m", "1 m", "1 m"] }/'
bad set_cuts_nothing "[rock_mass.joint_sets] 'steep'" "cuts no block" "origin, spacing and region"

# Sets that would never finish cutting (the parser replay, tests/fuzz/, found an origin 9e18 m away
# running for ever): refused with the numbers.
variant origin_far 's/^origin = \["0.3 m", "0 m"\]/origin = ["0.3 m", "9223372036854775808 m"]/'
bad origin_far "origin_far.toml:" "[rock_mass.joint_sets] 'steep'" "the origin lies 2.1e+18 spacings" "valid: within 1e+06"
variant spacing_tiny 's/^spacing = "1.5 m"/spacing = "1e-6 m"/'
bad spacing_tiny "[rock_mass.joint_sets] 'steep'" "parallel traces" "valid: at most 1e+05"
variant trace_tiny 's/^trace = .*/trace = "1e-7 m"/'
bad trace_tiny "[rock_mass.joint_sets]" "trace plus gap of" "pieces; valid: at most 1e+05"

variant gap_and_persistence 's/^persistence = 0.75/persistence = 0.75\ngap = "1 m"/'
bad gap_and_persistence "[rock_mass.joint_sets] 'flat'" "either gap or persistence"

variant unknown_key 's/^seed = 7/seeed = 7/'
bad unknown_key "unknown_key.toml:" "rock_mass.seeed" "valid keys:" "seed"

variant unknown_set 's/^joint_sets = \["steep", "flat", "fault"\]/joint_sets = ["steep", "flatt"]/'
bad unknown_set "joints.traces.joint_sets" "'flatt'" "fault, flat, steep"

variant bad_shape 's/^shape = "circle"/shape = "oval"/'
bad bad_shape "rock_mass.openings.shape" "unknown shape 'oval'" "circle, horseshoe, polygon"

# --seed N: another realisation of the same joint sets, as if the case said seed = N; the case's own
# seed is the case; names of numbered blocks (rm.<k>) are refused under another seed, since they
# are other blocks then (the case's fixed boundary names rm.0).
variant by_line 's/^block = "rm.0"/line = { from = ["0 m", "0 m"], to = ["10 m", "0 m"], tolerance = "1 mm" }/'
variant by_line_8 's/^block = "rm.0"/line = { from = ["0 m", "0 m"], to = ["10 m", "0 m"], tolerance = "1 mm" }/; s/^seed = 7/seed = 8/'
"$bin" run "$tmp/by_line.toml" --seed 8 --write-blocks "$tmp/seed_opt" --quiet >/dev/null 2>&1
"$bin" run "$tmp/by_line_8.toml" --write-blocks "$tmp/seed_file" --quiet >/dev/null 2>&1
"$bin" run "$tmp/by_line.toml" --write-blocks "$tmp/seed_own" --quiet >/dev/null 2>&1
if [ -s "$tmp/seed_opt/blocks.csv" ] && cmp -s "$tmp/seed_opt/blocks.csv" "$tmp/seed_file/blocks.csv" &&
   ! cmp -s "$tmp/seed_opt/blocks.csv" "$tmp/seed_own/blocks.csv"; then
  echo "ok   --seed 8 draws the blocks of seed = 8 ($(($(wc -l < "$tmp/seed_opt/blocks.csv") - 1)) blocks), not those of the case's seed 7"
else echo "FAIL --seed 8: blocks.csv not that of seed = 8, or that of seed 7"; fail=1; fi
if "$bin" run "$base" --seed 7 --write-blocks "$tmp/seed_7" --quiet >/dev/null 2>&1 && cmp -s "$tmp/seed_7/blocks.csv" "$tmp/blocks/blocks.csv"; then
  echo "ok   --seed 7 (the case's own) is the case, its numbered boundary block included"
else echo "FAIL --seed 7 is not the case itself"; fail=1; fi
# numbered blocks the command line names are chosen for the realisation it draws
expect seed_with_own_excavation 0 run "$tmp/by_line.toml" --seed 8 --excavate settle=rm.3 --write-blocks "$tmp/seed8_dug" -- "wrote"
expect seed_numbered_block 2 run "$base" --seed 8 --out "$tmp/out_seed8" --quiet -- \
  "sample.toml:78 key 'boundary.block'" "names block 'rm.0' by its number" "--seed 8" "select by location"
for v in -1 x 1.5 99999999999999999999; do
  expect "seed $v" 2 run "$base" --seed "$v" --out "$tmp/out_seed" --quiet -- "--seed $v" "give a whole number from 0 to 9223372036854775807"
done
expect seed_no_rock_mass 2 run "$src/cases/sliding_block/incline.toml" --seed 3 --out "$tmp/out_seed" --quiet -- \
  "--seed 3" "incline.toml has no [rock_mass] table"
expect seed_default 2 run --default --seed 3 --out "$tmp/out_seed" --quiet -- "--seed applies to DEM case files with a [rock_mass] table"
[ -e "$tmp/out_seed" ] && { echo "FAIL a refused --seed made an output folder"; fail=1; }

# --excavate STAGE=NAMES: the stage excavates these instead (here the opening, which the case's
# one stage leaves in place); bad forms are refused naming the option.
"$bin" run "$base" --excavate settle=drift --out "$tmp/run_dug" --quiet >/dev/null 2>&1
if n=$(/usr/bin/python3 -c "import h5py,sys; print(*(len(h5py.File(f'{d}/final_state.h5')['blocks/name']) for d in sys.argv[1:]))" "$tmp/run" "$tmp/run_dug" 2>&1) &&
   [ "${n% *}" -gt "${n#* }" ] && grep -q -- "--excavate settle=drift" "$tmp/run_dug/manifest.json"; then
  echo "ok   --excavate settle=drift removes the opening's blocks (blocks: $n)"
else echo "FAIL --excavate settle=drift: blocks $n"; fail=1; fi
expect excavate_no_stage 2 run "$base" --excavate setle=drift --out "$tmp/out_ex" --quiet -- "--excavate setle=..." "has no stage 'setle'" "did you mean 'settle'"
expect excavate_empty_name 2 run "$base" --excavate settle=drift,,rm.1 --out "$tmp/out_ex" --quiet -- "an empty name in the list"
expect excavate_twice 2 run "$base" --excavate settle=drift --excavate settle= --out "$tmp/out_ex" --quiet -- "stage 'settle' is given twice"
expect excavate_unknown 2 run "$base" --excavate settle=tunnel --out "$tmp/out_ex" --quiet -- \
  "given on the command line, or made by rockdem" "excavates 'tunnel', which is neither a block nor a block group"
expect excavate_no_form 2 run "$base" --excavate drift --out "$tmp/out_ex" --quiet -- "write STAGE=NAME,..."
[ -e "$tmp/out_ex" ] && { echo "FAIL a refused --excavate made an output folder"; fail=1; }

# An excavation that takes away every block a boundary on a line acts on (here the far-field
# strip under a fixed top) is refused before running: the model would lose that support
# silently. One that takes away some of them is a warning naming what the boundary keeps.
printf '\n[[stages]]\nname = "dig"\nexcavate = ["far_field"]\nuntil = "steps"\nsteps = 10\n' > "$tmp/dig.txt"
sed 's/^block = "rm.0"/line = { from = ["0 m", "10 m"], to = ["10 m", "10 m"], tolerance = "1 mm" }/' "$base" | cat - "$tmp/dig.txt" > "$tmp/lost_support.toml"
bad lost_support "lost_support.toml:76 [boundary]" "stage 'dig' excavates block" "on which this boundary acts, and no other block" \
  "limit the boundary to earlier stages"
sed 's/^block = "rm.0"/line = { from = ["0 m", "0 m"], to = ["0 m", "10 m"], tolerance = "1 mm" }/' "$base" | cat - "$tmp/dig.txt" > "$tmp/part_support.toml"
out=$("$bin" run "$tmp/part_support.toml" --out "$tmp/out_part" --quiet 2>&1); code=$?
if [ $code -eq 0 ] && grep -q "warning: .*part_support.toml:76 \[boundary\]: stage 'dig' excavates block rm\.[0-9]*, on which this boundary acts; it acts on rm\." <<<"$out"; then
  echo "ok   part of a boundary's blocks excavated: a warning naming what it keeps, and the run goes on"
else echo "FAIL part of a boundary's blocks excavated: exit $code: $out"; fail=1; fi

exit $fail
