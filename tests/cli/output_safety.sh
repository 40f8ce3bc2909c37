#!/usr/bin/env bash
# Nothing lost, nothing mixed (docs/reliability.md): a non-empty --out is refused unless
# --overwrite, which empties only a folder rockdem wrote; every run folder has a manifest.json
# (also as root attributes of history.h5); SIGINT/SIGTERM stop a run with exit 130/143, the state
# and the histories so far written, and a line saying how to go on; a full disk is exit 1 naming
# the path, never a crash; a result file (--out FILE, --json, --save-model, --write-case,
# --write-blocks) that exists is refused before the work unless --overwrite, and one that is an
# input (also a drive file a case names), a link, a device or in a missing folder always (exit 2).
# Usage: bash output_safety.sh <rockdem-binary> <source-dir>
set -u
bin=$1
src=$2
tmp=$(mktemp -d)
mnt=""
cleanup() {
  [ -n "$mnt" ] && umount "$mnt" 2>/dev/null
  rm -rf "$tmp"
}
trap cleanup EXIT
fail=0
. "$src/tests/cli/lib/expect.sh"
incline="$src/cases/sliding_block/incline.toml"
lab="$src/cases/direct_shear/test09_mohr_coulomb.toml"

# --- 3. output folders are never silently reused ------------------------------------------------
expect first_run 0 run "$incline" --out "$tmp/a" --quiet --
expect second_run_refused 2 run "$incline" --out "$tmp/a" --quiet -- "--out $tmp/a" "not empty" "--overwrite"
touch "$tmp/a/stale_from_earlier.vtu"
expect overwrite 0 run "$incline" --out "$tmp/a" --quiet --overwrite --
[ -e "$tmp/a/stale_from_earlier.vtu" ] && { echo "FAIL --overwrite left a stale file"; fail=1; }
mkdir -p "$tmp/mine" && echo "my notes" > "$tmp/mine/notes.txt"
expect overwrite_user_folder 2 run "$incline" --out "$tmp/mine" --quiet --overwrite -- "no" "manifest.json" "notes.txt"
[ -f "$tmp/mine/notes.txt" ] || { echo "FAIL the user's file was deleted"; fail=1; }
/usr/bin/python3 - "$tmp/a" "$incline" <<'PY' || fail=1
import json, sys, h5py
d, case = sys.argv[1], sys.argv[2]
m = json.load(open(d + "/manifest.json"))
want = {"status": "finished", "exit_code": 0, "stages": ["settle", "slide"], "case_file": case}
for k, v in want.items():
    if m.get(k) != v: print("FAIL manifest %s = %r, wanted %r" % (k, m.get(k), v)); sys.exit(1)
for k in ("rockdem_version", "rockdem_commit", "command_line", "started_utc", "ended_utc"):
    if not m.get(k): print("FAIL manifest lacks", k); sys.exit(1)
if "--overwrite" not in m["command_line"]: print("FAIL command line", m["command_line"]); sys.exit(1)
if open(d + "/case.toml").read() != open(case).read(): print("FAIL case.toml is not the case file"); sys.exit(1)
with h5py.File(d + "/history.h5", "r", locking=False) as f:
    a = dict(f.attrs)
    def s(x): return x.decode() if isinstance(x, bytes) else str(x)
    if s(a.get("status")) != "finished" or int(a.get("exit_code")) != 0 or s(a.get("stages")) != "settle, slide":
        print("FAIL history.h5 root attributes", a); sys.exit(1)
print("ok   manifest.json and history.h5 attributes: %s, commit %s, %s .. %s" % (m["status"], m["rockdem_commit"], m["started_utc"], m["ended_utc"]))
PY
# A restart continues the folder of the run it restarts (it has a manifest), no --overwrite needed.
cp -r "$tmp/a" "$tmp/b" && rm "$tmp/b/final_state.h5"
expect restart_same_folder 0 run "$incline" --out "$tmp/b" --restart "$tmp/b/stage_1_settle.h5" --quiet --
grep -q '"restart_from": ".*stage_1_settle.h5"' "$tmp/b/manifest.json" && grep -q '"status": "finished"' "$tmp/b/before_restart_1/manifest.json" ||
  { echo "FAIL restart: manifest not updated or the first run's manifest not kept"; fail=1; }
expect restart_foreign_folder 2 run "$incline" --out "$tmp/mine" --restart "$tmp/b/stage_1_settle.h5" --quiet -- "manifest.json"

# --- 4. SIGINT / SIGTERM ------------------------------------------------------------------------
# The built-in direct-shear case with a 5 mm stroke instead of 40 (about 15 s; this test also runs
# under the sanitizers): signalled one second into its second stage (after its first stage
# checkpoint), it must stop within seconds, leaving a checkpoint (interrupted_state.h5) that a
# restart goes on from as if nothing had happened: the SIGINT run, restarted in its own folder,
# ends with the uninterrupted run's history and test09.csv.
short="$tmp/short_stroke.toml"
sed 's/amplitude = "40 mm"/amplitude = "5 mm"/' "$src/cases/direct_shear/test09_coulomb.toml" > "$short"
grep -q 'amplitude = "5 mm"' "$short" || { echo "FAIL the short-stroke case was not made"; fail=1; }
"$bin" run "$short" --out "$tmp/sig_none" --quiet > "$tmp/sig_none.log" 2>&1 &
uninterrupted=$!
for sig in INT TERM; do
  want=$([ $sig = INT ] && echo 130 || echo 143)
  "$bin" run "$short" --out "$tmp/sig_$sig" --quiet > "$tmp/sig_$sig.log" 2>&1 &
  pid=$!
  for _ in $(seq 1 1200); do [ -f "$tmp/sig_$sig/stage_1_consolidate.h5" ] && break; sleep 0.1; done
  sleep 1
  kill -$sig $pid
  wait $pid
  code=$?
  out=$(cat "$tmp/sig_$sig.log")
  if [ $code -ne $want ]; then
    echo "FAIL SIG$sig: exit $code, wanted $want: $out"; fail=1; continue
  fi
  for w in "interrupted_state.h5" "--restart $tmp/sig_$sig/interrupted_state.h5"; do
    grep -qF -- "$w" <<<"$out" || { echo "FAIL SIG$sig: message lacks '$w': $out"; fail=1; }
  done
  /usr/bin/python3 - "$tmp/sig_$sig" $want <<'PY' || fail=1
import json, sys, h5py
d, code = sys.argv[1], int(sys.argv[2])
with h5py.File(d + "/history.h5", "r", locking=False) as f:
    n = f["history/time"].shape[0]
    t = f["history/time"][-1]
m = json.load(open(d + "/manifest.json"))
if m["status"] != "interrupted" or m["exit_code"] != code: print("FAIL manifest after signal", m); sys.exit(1)
h5py.File(d + "/interrupted_state.h5", "r", locking=False).close()
print("ok   signal: exit %d, history readable (%d samples to t = %.4f s), interrupted_state.h5 readable" % (code, n, t))
PY
  echo "     $(tail -n 1 <<<"$out")"
done
expect restart_from_interrupted 0 run "$short" --out "$tmp/sig_INT" --restart "$tmp/sig_INT/interrupted_state.h5" -- \
  "within stage 2" "resumed at step"
wait $uninterrupted || { echo "FAIL the uninterrupted default run: exit $?"; fail=1; }
/usr/bin/python3 - "$tmp/sig_none" "$tmp/sig_INT" <<'PY' || fail=1
import sys, filecmp, h5py, numpy as np
a, b = sys.argv[1:3]
A, B = (h5py.File(d + "/history.h5", "r", locking=False)["history"] for d in (a, b))
bad = [n for n in A if n not in B or not np.array_equal(A[n][()], B[n][()], equal_nan=True)]
same_csv = filecmp.cmp(a + "/test09.csv", b + "/test09.csv", shallow=False)
if bad or not same_csv: print("FAIL restarted after SIGINT: differs from the uninterrupted run:", bad, "test09.csv same:", same_csv); sys.exit(1)
print("ok   restarted after SIGINT from interrupted_state.h5: history (%d samples) and test09.csv identical to the uninterrupted run's" % len(A["time"]))
PY

# --- 3b. result files are never silently replaced ----------------------------------------------
# Every command's --out FILE, --json and --save-model: an existing file is refused before the work
# (exit 2, the file left as it was) unless --overwrite; an output that is one of the command's
# inputs, or another of its outputs, is refused even with --overwrite; checked before a fit runs.
twin="$src/cases/direct_shear/twins/test09.csv"
mkdir -p "$tmp/res"
keep() {  # name file: the file still holds what the user put there
  grep -qx "keep me" "$2" || { echo "FAIL $1: $2 was replaced"; fail=1; }
}
echo "keep me" > "$tmp/res/e.csv"
expect element_exists 2 element "$lab" --out "$tmp/res/e.csv" -- "--out $tmp/res/e.csv" "the file exists" "--overwrite"
keep element_exists "$tmp/res/e.csv"
expect element_overwrite 0 element "$lab" --out "$tmp/res/e.csv" --quiet --overwrite --
grep -q "^time_s," "$tmp/res/e.csv" || { echo "FAIL element --overwrite did not write the record"; fail=1; }
cp "$lab" "$tmp/res/lab.toml"
expect element_onto_case 2 element "$tmp/res/lab.toml" --out "$tmp/res/lab.toml" --overwrite -- "is the case file, an input" "even with --overwrite"
cmp -s "$lab" "$tmp/res/lab.toml" || { echo "FAIL element_onto_case: the case file changed"; fail=1; }
# A drive file the case reads (path = "file") is an input too.
mkdir -p "$tmp/res/t24/data"
cp "$src/cases/direct_shear/test24_barton_bandis.toml" "$tmp/res/t24/"
cp "$src/cases/direct_shear/data/test24_drive.csv" "$tmp/res/t24/data/"
expect element_onto_drive 2 element "$tmp/res/t24/test24_barton_bandis.toml" --out "$tmp/res/t24/data/test24_drive.csv" --overwrite -- \
  "is a drive file of the case, an input"
cmp -s "$src/cases/direct_shear/data/test24_drive.csv" "$tmp/res/t24/data/test24_drive.csv" || { echo "FAIL element_onto_drive: the drive changed"; fail=1; }
expect write_case_onto_drive 2 run "$tmp/res/t24/test24_barton_bandis.toml" --write-case "$tmp/res/t24/data/test24_drive.csv" --overwrite -- \
  "is a drive file of the case, an input"
# Not a plain file: a link (dangling or not) or a device is never written over.
ln -s "$tmp/res/nowhere.csv" "$tmp/res/dangling.csv"
expect element_onto_link 2 element "$lab" --out "$tmp/res/dangling.csv" --overwrite -- "not a plain file (a symbolic link)"
[ -L "$tmp/res/dangling.csv" ] || { echo "FAIL element_onto_link: the link was replaced"; fail=1; }
expect element_onto_device 2 element "$lab" --out /dev/null --overwrite -- "not a plain file (a device, pipe or socket)"
[ -c /dev/null ] || { echo "FAIL /dev/null is no longer a device"; fail=1; }
echo "a file" > "$tmp/res/afile"
expect element_parent_is_file 2 element "$lab" --out "$tmp/res/afile/e.csv" -- "'$tmp/res/afile' is a file, not a folder"
expect write_blocks_into_file 2 run "$src/cases/rock_mass/drift.toml" --write-blocks "$tmp/res/afile" -- "'$tmp/res/afile' is a file, not a folder"
expect element_folder 2 element "$lab" --out "$tmp/res" -- "is a folder"
expect element_no_folder 2 element "$lab" --out "$tmp/no/such/folder/e.csv" -- "the folder '$tmp/no/such/folder' does not exist"
echo "keep me" > "$tmp/res/c.json"
expect compare_json_exists 2 compare --data "$twin" --model "$tmp/res/e.csv" --json "$tmp/res/c.json" -- "--json $tmp/res/c.json" "the file exists"
keep compare_json_exists "$tmp/res/c.json"
expect compare_json_overwrite 0 compare --data "$twin" --model "$tmp/res/e.csv" --json "$tmp/res/c.json" --overwrite --quiet --
/usr/bin/python3 -c "import json,sys; json.load(open(sys.argv[1]))['nrmse']" "$tmp/res/c.json" || { echo "FAIL compare --overwrite json"; fail=1; }
cp "$twin" "$tmp/res/measured.csv"
expect compare_onto_data 2 compare --data "$tmp/res/measured.csv" --case "$lab" --save-model "$tmp/res/measured.csv" --overwrite -- \
  "--save-model $tmp/res/measured.csv: this is --data, an input"
cmp -s "$twin" "$tmp/res/measured.csv" || { echo "FAIL compare_onto_data: the measured record changed"; fail=1; }
expect compare_two_outputs 2 compare --data "$twin" --case "$lab" --save-model "$tmp/res/m.csv" --json "$tmp/res/m.csv" -- \
  "--json writes the same file"
echo "keep me" > "$tmp/res/fit.json"
# The refusals come before the inputs are read (and so before any fit): a broken measured record
# is not even looked at.
printf 'not a measurement record\n' > "$tmp/res/broken.csv"
expect calibrate_json_exists 2 calibrate --data "$twin" --law mohr_coulomb --json "$tmp/res/fit.json" -- "--json $tmp/res/fit.json" "the file exists"
keep calibrate_json_exists "$tmp/res/fit.json"
expect calibrate_model_onto_data 2 calibrate --data "$tmp/res/measured.csv" --law mohr_coulomb --save-model "$tmp/res/measured.csv" --overwrite -- \
  "this is --data, an input"
expect diagnose_json_exists 2 diagnose --data "$twin" --law mohr_coulomb --json "$tmp/res/fit.json" -- "the file exists"
keep diagnose_json_exists "$tmp/res/fit.json"
expect calibrate_before_reading 2 calibrate --data "$tmp/res/broken.csv" --law mohr_coulomb --json "$tmp/res/fit.json" -- "--json $tmp/res/fit.json: the file exists"
expect diagnose_before_reading 2 diagnose --data "$tmp/res/broken.csv" --law mohr_coulomb --json "$tmp/res/fit.json" -- "--json $tmp/res/fit.json: the file exists"
expect compare_before_reading 2 compare --data "$tmp/res/broken.csv" --model "$tmp/res/e.csv" --json "$tmp/res/c.json" -- "--json $tmp/res/c.json: the file exists"
expect diagnose_missing_data 2 diagnose --data "$tmp/res/none.csv" --law mohr_coulomb --json "$tmp/res/fit.json" -- "--data $tmp/res/none.csv: no such file"
expect diagnose_json_in_report 2 diagnose --data "$twin" --law mohr_coulomb --json "$tmp/res/rep/manifest.json" --report "$tmp/res/rep" -- \
  "is inside --report $tmp/res/rep"
[ -e "$tmp/res/rep" ] && { echo "FAIL diagnose_json_in_report: the report folder was made"; fail=1; }
echo "keep me" > "$tmp/res/drive.csv"
expect ground_motion_exists 2 ground-motion "$src/cases/data/ground_motions/mexico1985_sct_acc_g.txt" --column 3 --units g \
  --peak "1 mm" --out "$tmp/res/drive.csv" -- "--out $tmp/res/drive.csv" "the file exists"
keep ground_motion_exists "$tmp/res/drive.csv"
echo "keep me" > "$tmp/res/twin.csv"
expect virtual_lab_exists 2 virtual-lab "$src/cases/virtual_lab/test09.toml" --out "$tmp/res/twin.csv" -- "the file exists"
keep virtual_lab_exists "$tmp/res/twin.csv"
echo "keep me" > "$tmp/res/dem.toml"
expect write_case_exists 2 run "$lab" --write-case "$tmp/res/dem.toml" -- "--write-case $tmp/res/dem.toml" "the file exists"
keep write_case_exists "$tmp/res/dem.toml"
expect write_case_overwrite 0 run "$lab" --write-case "$tmp/res/dem.toml" --overwrite --quiet --
grep -q "^\[\[blocks\]\]" "$tmp/res/dem.toml" || { echo "FAIL --write-case --overwrite"; fail=1; }
expect write_blocks_first 0 run "$src/cases/rock_mass/drift.toml" --write-blocks "$tmp/res/blocks" --quiet --
expect write_blocks_again 2 run "$src/cases/rock_mass/drift.toml" --write-blocks "$tmp/res/blocks" --quiet -- \
  "--write-blocks $tmp/res/blocks/blocks.vtu: the file exists"
expect write_blocks_overwrite 0 run "$src/cases/rock_mass/drift.toml" --write-blocks "$tmp/res/blocks" --quiet --overwrite --

# --- 1d. write failures: exit 1 naming the path, never a crash ---------------------------------
mkdir -p "$tmp/full"
if mount -t tmpfs -o size=200k tmpfs "$tmp/full" 2>/dev/null; then
  mnt="$tmp/full"
  out=$(timeout 300 "$bin" run "$incline" --out "$tmp/full/run" --quiet 2>&1)
  code=$?
  if [ $code -ne 1 ] || ! grep -qF "$tmp/full/run" <<<"$out"; then
    echo "FAIL disk full run: exit $code (wanted 1 naming the path): $out"; fail=1
  else
    echo "ok   disk full run: exit 1: $(head -c 300 <<<"$out" | tr '\n' ' ')"
  fi
  umount "$mnt" && mnt=""
else
  echo "skip disk full (cannot mount a tmpfs here; needs root)"
fi

# --- 1e. progress: one updating line on a terminal, a line each in a pipe -----------------------
sed 's/^vtk_interval = 10000/vtk_interval = 10000\nprogress_seconds = "0.2 s"/' "$src/tests/cli/parallel/collapse.toml" > "$tmp/progress.toml"
# A progress line: "  <stage> <i>/<n>  step <N>  t = ...".
piped=$(timeout 300 "$bin" run "$tmp/progress.toml" --out "$tmp/progress_pipe" 2>&1 | grep -cE "^  [^ ]+ [0-9]+/[0-9]+  step ")
if command -v script >/dev/null; then
  timeout 300 script -qc "'$bin' run '$tmp/progress.toml' --out '$tmp/progress_tty'" /dev/null > "$tmp/tty.out" 2>&1
  updates=$(grep -oE $'\r  [^ ]+ [0-9]+/[0-9]+  step ' "$tmp/tty.out" | wc -l)
  lines=$(tr -d '\r' < "$tmp/tty.out" | grep -cE "^  [^ ]+ [0-9]+/[0-9]+  step ")
  if [ "$piped" -lt 3 ] || [ "$updates" -lt 3 ] || [ "$lines" -gt 1 ]; then
    echo "FAIL progress: $piped step lines in a pipe, $updates updates in $lines line(s) on a terminal"; fail=1
  else
    echo "ok   progress: $piped step lines in a pipe; on a terminal $updates updates of one line"
  fi
else
  echo "skip progress on a terminal (no 'script' command)"
fi
exit $fail
