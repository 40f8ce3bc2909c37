#!/usr/bin/env bash
# Restart: a run continued from a checkpoint repeats the uninterrupted run exactly, and its
# outputs hold the whole run as the uninterrupted run's do.
#  1. incline (rigid block on a slope), restarted from the end of its first stage into a new
#     folder: final state, history.h5 (every series, first sample after the restart included) bit
#     for bit; into its own folder: the same, with the earlier run's files in before_restart_1/.
#  2. seismic column (energy histories): restarted after the shaking, the energy balance goes on
#     from its terms: every series bit for bit.
#  3. a laboratory test (test 8, Mohr-Coulomb, 1000 mm/s): run with one test stage, then continued
#     from final_state.h5 with two: history and joint record (test08.csv) equal to the two-stage
#     run's; from the end of its third stage (between two test stages): the same.
#  4. refused, exit 2, with the differing key named: a changed joint stiffness; a changed
#     completed stage; final_state.h5 of a case with nothing left to run. Accepted: a changed
#     stage still to run.
#  5. checkpoints within stages (--checkpoint-every, [output] checkpoint_every/_keep): they change
#     nothing in the run; a restart from any of them repeats the rest of the run bit for bit (final
#     state, history, joint record, drift results): the incline (a checkpoint inside a chunk of
#     steps), the seismic column during its shaking (compliant base, energy balance), test 8 within
#     a shear stage, and an excavation with a gradual release (relax) on a jointed rock mass with
#     drift results; into its own folder; the stage under way may not change, a later one may;
#     bad checkpoint intervals refused.
# Usage: bash run_restart.sh <rockdem-binary> <source-dir>
set -u
bin=$1
src=$2
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
py=/usr/bin/python3
fail=0
ok() { echo "ok   $*"; }
bad() { echo "FAIL $*"; fail=1; }

# same_history A B: every series of A's history.h5 equals B's, bit for bit.
same_history() {
  "$py" - "$1/history.h5" "$2/history.h5" <<'PY'
import sys, h5py, numpy as np
a, b = (h5py.File(f, "r", locking=False) for f in sys.argv[1:3])
bad = [n for n in a["history"] if n not in b["history"] or a["history"][n].shape != b["history"][n].shape
       or not np.array_equal(a["history"][n][()], b["history"][n][()], equal_nan=True)]
if bad: print("  series that differ:", bad); sys.exit(1)
print("  %d series x %d samples identical" % (len(a["history"]), len(a["history/time"])))
PY
}

# --- 1. incline ----------------------------------------------------------------------------------
incline="$src/cases/sliding_block/incline.toml"
"$bin" run "$incline" --out "$tmp/full" --quiet || { echo "FAIL full run"; exit 1; }
"$bin" run "$incline" --out "$tmp/new" --restart "$tmp/full/stage_1_settle.h5" --quiet || bad "restart into a new folder: exit $?"
"$py" - "$tmp/full/final_state.h5" "$tmp/new/final_state.h5" <<'PY' && ok "incline restarted: final state bit for bit" || bad "incline restarted: final state differs"
import sys, h5py, numpy as np
a, b = (h5py.File(f, "r", locking=False) for f in sys.argv[1:3])
for name in ("gridpoints/x", "gridpoints/v", "blocks/xc", "blocks/vc", "contacts/state", "contacts/sigma_n"):
    if not np.array_equal(a[name][()], b[name][()]): print("  differs in", name); sys.exit(1)
PY
same_history "$tmp/full" "$tmp/new" && ok "incline restarted into a new folder: history.h5 holds the whole run" ||
  bad "incline restarted into a new folder: history differs"
cp -r "$tmp/full" "$tmp/same"
"$bin" run "$incline" --out "$tmp/same" --restart "$tmp/same/stage_1_settle.h5" --quiet || bad "restart into its own folder: exit $?"
same_history "$tmp/full" "$tmp/same" && ok "incline restarted into its own folder: history.h5 holds the whole run" ||
  bad "incline restarted into its own folder: history differs"
for f in history.h5 final_state.h5 manifest.json stage_2_slide.h5 vtk/blocks.pvd; do
  [ -f "$tmp/same/before_restart_1/$f" ] || bad "the earlier run's $f was not set aside in before_restart_1/"
done
[ -f "$tmp/same/stage_1_settle.h5" ] && [ -f "$tmp/same/stage_2_slide.h5" ] || bad "stage checkpoints missing after the restart"
# The earlier frames after the restart's step were set aside, those up to it stayed.
aside=$(ls "$tmp/same/before_restart_1/vtk" | grep -c '\.pvtu$')
kept=$(ls "$tmp/same/vtk" | grep -c '\.pvtu$')
all=$(ls "$tmp/full/vtk" | grep -c '\.pvtu$')
[ "$aside" -gt 0 ] && [ "$kept" -eq "$all" ] && ok "VTK frames: $aside of the earlier run's set aside, the series complete again ($kept)" ||
  bad "VTK frames: $aside set aside, $kept in vtk/ (the uninterrupted run has $all)"
cmp -s "$tmp/full/history.h5" "$tmp/same/before_restart_1/history.h5" && ok "the earlier run's files kept in before_restart_1/" ||
  bad "the earlier run's history.h5 was changed"

# --- 2. energy histories -------------------------------------------------------------------------
column="$src/cases/verification/seismic_column/column.toml"
"$bin" run "$column" --out "$tmp/col" --quiet --no-plots || bad "column run: exit $?"
"$bin" run "$column" --out "$tmp/colr" --restart "$tmp/col/stage_1_shake.h5" --quiet --no-plots || bad "column restart: exit $?"
same_history "$tmp/col" "$tmp/colr" && ok "seismic column restarted after the shaking: energy balance and every history bit for bit" ||
  bad "seismic column restarted: history differs"

# --- 3. laboratory test, continued stage by stage ------------------------------------------------
lab="$src/cases/direct_shear/test08_mohr_coulomb.toml"
fast=(--shear-velocity "1000 mm/s" --quiet)
"$bin" run "$lab" --stages 2 "${fast[@]}" --out "$tmp/lab2" || bad "lab 2 stages: exit $?"
"$bin" run "$lab" --stages 1 "${fast[@]}" --out "$tmp/lab1" || bad "lab 1 stage: exit $?"
"$bin" run "$lab" --stages 2 "${fast[@]}" --out "$tmp/lab12" --restart "$tmp/lab1/final_state.h5" || bad "lab continued from final_state.h5: exit $?"
same_history "$tmp/lab2" "$tmp/lab12" && cmp -s "$tmp/lab2/test08.csv" "$tmp/lab12/test08.csv" &&
  ok "test 8 run with one test stage, continued from final_state.h5 with two: history and test08.csv identical" ||
  bad "test 8 continued from final_state.h5: history or record differs"
"$bin" run "$lab" --stages 2 "${fast[@]}" --out "$tmp/lab3" --restart "$tmp/lab2/stage_3_load_2.h5" || bad "lab restart between test stages: exit $?"
same_history "$tmp/lab2" "$tmp/lab3" && cmp -s "$tmp/lab2/test08.csv" "$tmp/lab3/test08.csv" &&
  ok "test 8 restarted between its test stages: history and test08.csv identical" || bad "test 8 restarted between test stages: differs"

# --- 4. what a restart may change ----------------------------------------------------------------
# expect NAME CODE ARGS... -- SUBSTRINGS... (exit code and every substring in the message)
source "$src/tests/cli/lib/expect.sh"
sed 's/^kn = "10 GPa\/m"/kn = "1 GPa\/m"/' "$incline" > "$tmp/kn.toml"
expect changed_stiffness_refused 2 run "$tmp/kn.toml" --out "$tmp/kn" --restart "$tmp/full/stage_1_settle.h5" --quiet -- \
  "joints[0].kn" "10 GPa/m" "1 GPa/m" "from the start"
[ -e "$tmp/kn" ] && bad "a refused restart created its folder"
sed 's/^ratio = 1e-7/ratio = 1e-6/' "$incline" > "$tmp/ratio.toml"
expect changed_completed_stage_refused 2 run "$tmp/ratio.toml" --out "$tmp/ratio" --restart "$tmp/full/stage_1_settle.h5" --quiet -- \
  "stages[0].ratio: 1e-07 in the checkpoint's case, 1e-06 in this one"
sed 's/^duration = "1 s"/duration = "0.5 s"/' "$incline" > "$tmp/later.toml"
expect changed_stage_to_run_accepted 0 run "$tmp/later.toml" --out "$tmp/later" --restart "$tmp/full/stage_1_settle.h5" -- \
  "restarting from"
expect nothing_left_refused 2 run "$incline" --out "$tmp/none" --restart "$tmp/full/final_state.h5" --quiet -- \
  "ends the case's last stage" "nothing is left to run"
expect other_case_refused 2 run "$src/cases/direct_shear/test09_coulomb.toml" --out "$tmp/other" --restart "$tmp/full/stage_1_settle.h5" --quiet -- \
  "stage_1_settle.h5: this case differs"

# --- 5. checkpoints within stages -----------------------------------------------------------------
# same_state A B: the final states (every dataset but the block names) are equal, bit for bit.
same_state() {
  "$py" - "$1/final_state.h5" "$2/final_state.h5" <<'PY'
import sys, h5py
a, b = (h5py.File(f, "r", locking=False) for f in sys.argv[1:3])
bad = []
for g in ("gridpoints", "zones", "blocks", "contacts"):
    for n in a[g]:
        if n != "name" and (n not in b[g] or a[g][n][()].tobytes() != b[g][n][()].tobytes()): bad.append(g + "/" + n)
if bad: print("  final state differs in", bad); sys.exit(1)
PY
}
# restart_each DIR CASE ARGS...: restarts CASE from every checkpoint_step_*.h5 in DIR into a new
# folder and compares final state and history with DIR's; prints how many matched.
restart_each() {
  local dir=$1 case_file=$2 n=0 k
  shift 2
  for k in "$dir"/checkpoint_step_*.h5; do
    local r="$dir-r$(basename "$k" .h5)"
    # (messages to standard error: standard output is the count)
    "$bin" run "$case_file" --out "$r" --restart "$k" --quiet --no-plots "$@" >"$r.log" 2>&1 || { echo "     restart from $k: exit $?: $(tail -2 "$r.log")" >&2; continue; }
    if same_state "$dir" "$r" >/dev/null && same_history "$dir" "$r" >/dev/null; then n=$((n + 1)); else echo "     restart from $k: differs" >&2; fi
  done
  echo $n
}
"$bin" run "$incline" --out "$tmp/ck" --checkpoint-every "1000 steps" > "$tmp/ck.log" || bad "incline with checkpoints: exit $?"
same_state "$tmp/full" "$tmp/ck" && same_history "$tmp/full" "$tmp/ck" >/dev/null &&
  ok "incline: checkpoints within stages change nothing in the run (final state, history)" || bad "incline: the checkpoints changed the run"
# The newest three of those the run wrote (its progress lines name each) are kept.
kept=$(ls "$tmp/ck" | grep '^checkpoint_step_.*\.h5$' | sort | tr '\n' ' ')
newest=$(grep -o 'checkpoint_step_[0-9]*\.h5' "$tmp/ck.log" | tail -3 | sort | tr '\n' ' ')
written=$(grep -c 'checkpoint_step_' "$tmp/ck.log")
[ "$written" -gt 3 ] && [ "$kept" = "$newest" ] && ok "incline: of $written checkpoints written the newest 3 kept (checkpoint_keep's default)" ||
  bad "incline: kept '$kept', the newest 3 written '$newest' ($written written)"
# One falls inside a chunk of steps (its step is no multiple of 10: at a contact detection).
inside=$("$py" -c "
import glob, h5py
print(sum(1 for f in glob.glob('$tmp/ck/checkpoint_step_*.h5') if h5py.File(f, 'r', locking=False)['extra'].attrs['stage_into_chunk'] > 0))")
m=$(restart_each "$tmp/ck" "$incline" | tail -1)
[ "$m" = 3 ] && [ "$inside" -ge 1 ] && ok "incline restarted from each of its 3 checkpoints ($inside inside a chunk): final state and history bit for bit" ||
  bad "incline restarts from checkpoints within stages: $m of 3 identical, $inside inside a chunk"
# Into its own folder: the earlier run's files set aside, the history whole again.
k=$(ls "$tmp/ck" | grep '^checkpoint_step_' | sort -t_ -k3 -n | head -1)
cp -r "$tmp/ck" "$tmp/ckown"
"$bin" run "$incline" --out "$tmp/ckown" --restart "$tmp/ckown/$k" --quiet || bad "restart into its own folder from $k: exit $?"
same_history "$tmp/full" "$tmp/ckown" >/dev/null && [ -f "$tmp/ckown/before_restart_1/history.h5" ] && [ -f "$tmp/ckown/$k" ] &&
  ok "incline restarted into its own folder from $k: history whole, the earlier run's set aside" || bad "incline restarted into its own folder from $k"

# The seismic column: checkpoints during the shaking (the case's own [output] keys, all kept;
# its motion file named with an absolute path in the copy).
colck="$tmp/column_ck.toml"
sed -e 's/^\[output\]/[output]\ncheckpoint_every = "3000 steps"\ncheckpoint_keep = 0/' \
    -e "s|^file = \"\.\./\.\./data/|file = \"$(cd "$src" && pwd)/cases/data/|" "$column" > "$colck"
"$bin" run "$colck" --out "$tmp/colck" --quiet --no-plots || bad "column with checkpoints: exit $?"
same_history "$tmp/col" "$tmp/colck" >/dev/null || bad "column: the checkpoints changed the run"
shake=$("$py" -c "
import glob, h5py
print(sum(1 for f in glob.glob('$tmp/colck/checkpoint_step_*.h5') if h5py.File(f, 'r', locking=False)['extra'].attrs['stages_completed'] == 0))")
# Restarted with the case without those keys: they do not count as a difference.
sed -e '/^checkpoint_every = "3000 steps"$/d' -e '/^checkpoint_keep = 0$/d' "$colck" > "$tmp/column_plain.toml"
m=$(restart_each "$tmp/colck" "$tmp/column_plain.toml" | tail -1)
all=$(ls "$tmp/colck" | grep -c '^checkpoint_step_')
[ "$m" = "$all" ] && [ "$shake" -ge 3 ] && ok "seismic column restarted from each of $all checkpoints ($shake during the shaking): energy balance and every history bit for bit" ||
  bad "seismic column: $m of $all restarts identical ($shake during the shaking)"

# Within the shaking, the stage after it may change.
sed 's/^duration = "0.5 s"/duration = "0.2 s"/' "$tmp/column_plain.toml" > "$tmp/column_later.toml"
kc=$(ls "$tmp/colck" | grep '^checkpoint_step_' | sort -t_ -k3 -n | head -1)
expect within_later_stage_changed_accepted 0 run "$tmp/column_later.toml" --out "$tmp/w2" --restart "$tmp/colck/$kc" --no-plots -- \
  "restarting from" "within stage 1" "resumed at step"

# Test 8 within its shear stages: the joint record too.
"$bin" run "$lab" --stages 2 "${fast[@]}" --out "$tmp/labck" --checkpoint-every "3000 steps" || bad "lab with checkpoints: exit $?"
m=0
for k in "$tmp/labck"/checkpoint_step_*.h5; do
  r="$tmp/labck-$(basename "$k" .h5)"
  "$bin" run "$lab" --stages 2 "${fast[@]}" --out "$r" --restart "$k" || bad "lab restart from $k: exit $?"
  same_history "$tmp/lab2" "$r" >/dev/null && cmp -s "$tmp/lab2/test08.csv" "$r/test08.csv" && m=$((m + 1))
done
shearing=$("$py" -c "
import glob, h5py
print(sum(1 for f in glob.glob('$tmp/labck/checkpoint_step_*.h5') if h5py.File(f, 'r', locking=False)['arrays/lab_record.stage_reference'][0] > 0))")
[ "$m" -eq 3 ] && [ "$shearing" -ge 1 ] && ok "test 8 restarted from 3 checkpoints within its stages ($shearing within a shear stage): history and test08.csv identical" ||
  bad "test 8 restarted within its stages: $m of 3 identical, $shearing within a shear stage"

# An excavation released over 400 steps (relax) in a jointed rock mass with drift results: a
# restart within the excavation stage rebuilds the release where it was.
# (local damping in that stage: the damping's running averages come back too)
sed -e '/^excavate = \["opening"\]/{n;/^damping = "none"/d}' "$src/tests/cli/drift/results.toml" |
  sed -e 's/^excavate = \["opening"\]/excavate = ["opening"]\nrelax_steps = 400/' \
      -e 's/^steps = 100$/steps = 600/' -e 's/^\[output\]/[output]\ncheckpoint_keep = 0/' > "$tmp/relax.toml"
relax="$tmp/relax.toml"
grep -q '^relax_steps = 400' "$relax" && [ "$(grep -A3 '^excavate = ' "$relax" | grep -c '^damping')" -eq 0 ] || bad "the relax case was not made"
"$bin" run "$relax" --out "$tmp/rx" --quiet --checkpoint-every "250 steps" || bad "relax case: exit $?"
m=0 n=0
for k in "$tmp/rx"/checkpoint_step_*.h5; do
  [ "$("$py" -c "import h5py; print('stage.relax' in h5py.File('$k', 'r', locking=False)['arrays'])")" = True ] || continue
  n=$((n + 1))
  r="$tmp/rx-$(basename "$k" .h5)"
  "$bin" run "$relax" --out "$r" --restart "$k" --quiet || { bad "relax restart from $k: exit $?"; continue; }
  same=1
  same_state "$tmp/rx" "$r" >/dev/null && same_history "$tmp/rx" "$r" >/dev/null || same=0
  for f in events.csv contacts_4_settle.csv; do  # the header names the case file, the rest must match
    cmp -s <(tail -n +2 "$tmp/rx/drift/$f") <(tail -n +2 "$r/drift/$f") || same=0
  done
  m=$((m + same))
done
[ "$n" -ge 2 ] && [ "$m" -eq "$n" ] && ok "excavation with a gradual release: restarted from $n checkpoints within it, state, history and drift results identical" ||
  bad "excavation with a gradual release: $m of $n restarts within it identical"

# The stage under way ran in part with the checkpoint's case: it may not change; a later one may.
k=$(ls "$tmp/ck" | grep '^checkpoint_step_' | sort -t_ -k3 -n | head -1)
sed 's/^duration = "1 s"/duration = "0.5 s"/' "$incline" > "$tmp/later2.toml"
expect within_changed_stage_refused 2 run "$tmp/later2.toml" --out "$tmp/w1" --restart "$tmp/ck/$k" --quiet -- \
  "stages[1].duration" "run the changed case from the start"
expect bad_interval_zero 2 run "$incline" --out "$tmp/b1" --checkpoint-every "0 steps" -- "--checkpoint-every" "positive whole number"
expect bad_interval_words 2 run "$incline" --out "$tmp/b2" --checkpoint-every "often" -- "--checkpoint-every" "30 min"
expect bad_interval_negative 2 run "$incline" --out "$tmp/b3" --checkpoint-every "-5 min" -- "--checkpoint-every" "must be a positive"
sed 's/^\[output\]/[output]\ncheckpoint_every = 5000/' "$incline" > "$tmp/every.toml"
expect bad_case_interval 2 run "$tmp/every.toml" --out "$tmp/b5" -- "output.checkpoint_every" "N steps"
sed 's/^\[output\]/[output]\ncheckpoint_keep = -1/' "$incline" > "$tmp/keep.toml"
expect bad_keep 2 run "$tmp/keep.toml" --out "$tmp/b4" -- "output.checkpoint_keep" "keep all"
exit $fail

