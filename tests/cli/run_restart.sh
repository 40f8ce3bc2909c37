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
aside=$(ls "$tmp/same/before_restart_1/vtk" | grep -c '\.vtu$')
kept=$(ls "$tmp/same/vtk" | grep -c '\.vtu$')
all=$(ls "$tmp/full/vtk" | grep -c '\.vtu$')
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
exit $fail
