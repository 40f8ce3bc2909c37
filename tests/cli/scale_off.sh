#!/usr/bin/env bash
# Scaling of loose blocks (a stage's scale_off; cases/excavation/crown.toml): the crown block
# that falls when the opening is excavated is taken out once it has moved 0.1 m, and the stage
# then reaches its equilibrium (without scale_off it does not, exit 3); scaled_off.csv names it;
# a block a history names is kept, with a warning. The run repeats itself exactly on 2 and 3
# processes and from restarts: the first stage's checkpoint, checkpoints within the stage before
# and after the block was taken out (2 processes), the checkpoint at the removal's own detection
# (energy tracked), and a stage added after it; a run stopped after a removal keeps its record.
# Identical means every dataset equal, the sums over processes to 1e-12 relative. Bad values refused.
# Usage: bash scale_off.sh <rockdem-binary> <source-dir>
set -u
bin=$1
src=$(cd "$2" && pwd)
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_rmaps_base_oversubscribe=1
py=/usr/bin/python3
fail=0
case=$src/cases/excavation/crown.toml

# same A B: final state and history identical (the sums over processes to 1e-12 relative).
same() {
  "$py" - "$1" "$2" <<'PY'
import sys, h5py, numpy as np
a, b = sys.argv[1:3]
summed = {"history/ratio", "history/kinetic", "history/unbalanced_ratio", "arrays/engine.step_values", "arrays/energy.terms"}
bad, n = [], 0
for name in ("history.h5", "final_state.h5"):
    A, B = h5py.File(f"{a}/{name}", "r"), h5py.File(f"{b}/{name}", "r")
    keys = []
    A.visititems(lambda k, o: keys.append(k) if isinstance(o, h5py.Dataset) else None)
    for k in keys:
        if k not in B: bad.append(f"{name}:{k} missing"); continue
        x, y = A[k][()], B[k][()]
        n += 1
        if x.shape != y.shape: bad.append(f"{name}:{k} shape {x.shape} vs {y.shape}"); continue
        if k in summed and x.dtype.kind == "f":
            s = np.nanmax(np.abs(x)) if x.size else 0.0
            if s > 0 and not np.nanmax(np.abs(x - y)) / s <= 1e-12: bad.append(f"{name}:{k} differs")
        elif not np.array_equal(x, y, equal_nan=x.dtype.kind == "f"):
            bad.append(f"{name}:{k} differs")
print("; ".join(bad[:5]) if bad else f"{n} datasets identical")
sys.exit(1 if bad else 0)
PY
}

# 1. The serial run: the key block is taken out, the stage converges, six blocks remain.
if "$bin" run "$case" --out "$tmp/s" --checkpoint-every "500 steps" >"$tmp/s.log" 2>&1; then
  if grep -q "scaled off 1 block that moved more than 0.1 m in stage 'excavate': key (0.101 m" "$tmp/s.log" &&
     grep -q "^  scaled_off.csv " "$tmp/s.log" &&  # named in the run's closing list of outputs
     r=$("$py" - "$tmp/s" <<'PY'
import sys, csv, h5py
d = sys.argv[1]
rows = [r for r in csv.DictReader(l for l in open(d + "/scaled_off.csv") if not l.startswith("#"))]
assert len(rows) == 1 and rows[0]["block"] == "key" and rows[0]["stage_name"] == "excavate", rows
assert 0.1 < float(rows[0]["moved_m"]) < 0.11 and abs(float(rows[0]["area_m2"]) - 0.8) < 1e-3, rows
f = h5py.File(d + "/final_state.h5", "r")
n = len(f["blocks/density"])
assert n == 5, f"{n} blocks in the final state, 5 wanted (7 less the opening and the key)"
print(f"key taken out after {float(rows[0]['moved_m']):.4f} m at step {rows[0]['step']}; {n} blocks remain")
PY
); then echo "ok   the crown block is scaled off: $r"
  else echo "FAIL scaled off: ${r:-}"; cat "$tmp/s.log"; fail=1; fi
else
  echo "FAIL the crown case: exit $?"; tail -5 "$tmp/s.log"; fail=1
fi
# The step of the removal (that run's detection that took the key block out), and the kept
# checkpoints of that run just before and just after it, for the checks below.
removal=$(awk -F, '/^2,excavate,[0-9]+,key,/{print $3}' "$tmp/s/scaled_off.csv" 2>/dev/null)
before=$(ls "$tmp/s" | sed -n 's/^checkpoint_step_\([0-9]*\)\.h5$/\1/p' | sort -n | awk -v r="${removal:-0}" '$1 < r' | tail -1)
after=$(ls "$tmp/s" | sed -n 's/^checkpoint_step_\([0-9]*\)\.h5$/\1/p' | sort -n | awk -v r="${removal:-0}" '$1 > r' | head -1)
[ -n "$removal" ] && [ -n "$before" ] && [ -n "$after" ] && echo "ok   removal at step $removal; checkpoints at $before and $after around it" ||
  { echo "FAIL the removal's step (${removal:-none}) or the checkpoints around it (${before:-none}, ${after:-none})"; fail=1; removal=0; }
# Without scale_off the falling block keeps the stage from its equilibrium.
grep -v '^scale_off' "$case" > "$tmp/none.toml"
"$bin" run "$tmp/none.toml" --out "$tmp/none" --quiet >"$tmp/none.log" 2>&1
code=$?
# The message says where the model still moves: the falling key block.
if [ $code -eq 3 ] && grep -q "did not reach equilibrium" "$tmp/none.log" && grep -q "fastest gridpoint: block 'key' near" "$tmp/none.log"; then
  echo "ok   without scale_off the stage does not reach equilibrium (exit 3) and names the falling block ($(grep -o "fastest gridpoint: [^)]*) m at [0-9.e+-]* m/s" "$tmp/none.log"))"
else echo "FAIL without scale_off: exit $code"; cat "$tmp/none.log"; fail=1; fi
# A block a history names is not taken out: said once, and the stage fails as without scale_off.
cp "$case" "$tmp/held.toml"
printf '\n[[histories]]\nname = "key_dy"\nquantity = "face_displacement"\nblock = "key"\nface = "bottom"\ncomponent = "y"\n' >> "$tmp/held.toml"
"$bin" run "$tmp/held.toml" --out "$tmp/held" --quiet >"$tmp/held.log" 2>&1
code=$?
if [ $code -eq 3 ] && [ "$(grep -c "block 'key' has moved .* and is not taken out" "$tmp/held.log")" -eq 1 ] &&
   [ -f "$tmp/held/scaled_off.csv" ] && ! grep -q "^2,excavate" "$tmp/held/scaled_off.csv"; then echo "ok   a block a history names is kept, with one warning"
else echo "FAIL held block: exit $code"; cat "$tmp/held.log"; fail=1; fi

# A run stopped after a removal keeps its record: the stage cut at max_steps 100 steps after it.
sed 's/^max_steps = 40000/max_steps = 14700/' "$case" > "$tmp/cut.toml"
"$bin" run "$tmp/cut.toml" --out "$tmp/cut" --quiet >"$tmp/cut.log" 2>&1
code=$?
if [ $code -eq 3 ] && grep -q "^2,excavate,$removal,key," "$tmp/cut/scaled_off.csv"; then echo "ok   a run stopped after the removal (exit 3) keeps scaled_off.csv"
else echo "FAIL a run stopped after the removal: exit $code, $(cat "$tmp/cut/scaled_off.csv" 2>&1)"; fail=1; fi

# 2. On 2 and 3 processes: the serial run's results.
for np in 2 3; do
  if timeout 600 mpirun -np $np "$bin" run "$case" --out "$tmp/p$np" --quiet >"$tmp/p$np.log" 2>&1 && r=$(same "$tmp/s" "$tmp/p$np") &&
     cmp -s "$tmp/s/scaled_off.csv" "$tmp/p$np/scaled_off.csv"; then echo "ok   on $np processes: $r, scaled_off.csv the same"
  else echo "FAIL on $np processes: ${r:-}"; tail -5 "$tmp/p$np.log"; fail=1; fi
  r=
done

# 3. Restarts (on 2 processes) from the first stage's end and from within the stage before and
# after the block was taken out: the uninterrupted run's results.
for k in stage_1_settle "checkpoint_step_$before" "checkpoint_step_$after"; do
  if [ ! -f "$tmp/s/$k.h5" ]; then echo "FAIL no $k.h5 to restart from: $(ls "$tmp/s" | tr '\n' ' ')"; fail=1; continue; fi
  cp -r "$tmp/s" "$tmp/r_$k"
  if timeout 600 mpirun -np 2 "$bin" run "$case" --out "$tmp/r_$k" --restart "$tmp/r_$k/$k.h5" --quiet >"$tmp/r_$k.log" 2>&1 &&
     r=$(same "$tmp/s" "$tmp/r_$k") && cmp -s "$tmp/s/scaled_off.csv" "$tmp/r_$k/scaled_off.csv"; then echo "ok   restart from $k on 2 processes: $r"
  else echo "FAIL restart from $k: ${r:-}"; tail -5 "$tmp/r_$k.log"; fail=1; fi
  r=
done
# extended NAME STAGES CHECKPOINT WHAT: the case with STAGES (TOML text) added, run whole and
# restarted from its CHECKPOINT: the same results.
extended() {
  cp "$case" "$tmp/$1.toml"
  printf '%b' "$2" >> "$tmp/$1.toml"
  "$bin" run "$tmp/$1.toml" --out "$tmp/$1" --quiet >/dev/null 2>&1
  cp -r "$tmp/$1" "$tmp/$1_r"
  if "$bin" run "$tmp/$1.toml" --out "$tmp/$1_r" --restart "$tmp/$1_r/$3.h5" --quiet >"$tmp/$1_r.log" 2>&1 &&
     r=$(same "$tmp/$1" "$tmp/$1_r"); then echo "ok   $4: $r"
  else echo "FAIL $4: ${r:-}"; tail -3 "$tmp/$1_r.log"; fail=1; fi
  r=
}
# A stage added after the scaling: from the stage checkpoint (the key taken out again on the way).
extended more '\n[[stages]]\nname = "rest"\nuntil = "steps"\nsteps = 200\n' stage_2_excavate \
  "a stage added after the scaling, from the stage checkpoint"
# A later stage that excavates the block scale_off took out (it takes out nothing then): a restart
# after that stage makes the removals again and accepts that the excavation removed nothing.
extended dig '\n[[stages]]\nname = "dig"\nexcavate = ["key"]\nuntil = "steps"\nsteps = 100\n\n[[stages]]\nname = "rest"\nuntil = "steps"\nsteps = 100\n' \
  stage_3_dig "an excavation of the block already scaled off, restarted after it"

# A checkpoint written at the detection the removal makes, with the energy balance tracked (an
# energy history): the balance's per-item arrays are made again only by the next step, so the
# checkpoint carries its terms alone; a restart from it goes on as the run did. The stage is cut
# 40 steps after the removal (at 14,600 of its steps) so that the kept checkpoints include it.
"$py" - "$case" "$tmp/en.toml" <<'PY'
import sys
s = open(sys.argv[1]).read()
t = s.replace("max_steps = 40000", 'max_steps = 14640\nat_max_steps = "continue"')
assert t != s
t += '\n[[histories]]\nname = "energy_kinetic"\nquantity = "energy"\ncomponent = "kinetic"\n\n[output]\ncheckpoint_keep = 5\n'
open(sys.argv[2], "w").write(t)
PY
if "$bin" run "$tmp/en.toml" --out "$tmp/en" --quiet --checkpoint-every "10 steps" >"$tmp/en.log" 2>&1 && [ -f "$tmp/en/checkpoint_step_$removal.h5" ] &&
   "$py" -c "
import sys, h5py
k = sorted(x for x in h5py.File(sys.argv[1], 'r')['arrays'].keys() if x.startswith('energy'))
sys.exit(0 if k == ['energy.dt_prev', 'energy.scale', 'energy.terms'] else 1)" "$tmp/en/checkpoint_step_$removal.h5"; then
  cp -r "$tmp/en" "$tmp/en_r"
  if "$bin" run "$tmp/en.toml" --out "$tmp/en_r" --restart "$tmp/en_r/checkpoint_step_$removal.h5" --quiet >"$tmp/en_r.log" 2>&1 &&
     r=$(same "$tmp/en" "$tmp/en_r"); then echo "ok   restart from the checkpoint at the removal's detection (energy terms alone): $r"
  else echo "FAIL restart from the checkpoint at the removal: ${r:-}"; tail -3 "$tmp/en_r.log"; fail=1; fi
else
  echo "FAIL no checkpoint at the removal's detection with the energy terms alone: $(ls "$tmp/en" | tr '\n' ' ')"; tail -3 "$tmp/en.log"; fail=1
fi
r=

# 4. Bad values and places.
. "$src/tests/cli/lib/expect.sh"
for v in '"0 m"' '"-1 m"' '"x"' '0.1' '"1 s"'; do
  sed "s/^scale_off = .*/scale_off = $v/" "$case" > "$tmp/bad.toml"
  expect "scale_off = $v" 2 run "$tmp/bad.toml" --out "$tmp/bad" --quiet -- "bad.toml:" "stages.excavate.scale_off"
done
"$py" - "$case" "$tmp/steps.toml" <<'PY'
import sys
s = open(sys.argv[1]).read()
t = s.replace('until = "equilibrium"\nratio = 1e-5\nmax_steps = 40000', 'until = "steps"\nsteps = 100')
assert t != s
open(sys.argv[2], "w").write(t)
PY
expect "scale_off in a stage of fixed steps" 2 run "$tmp/steps.toml" --out "$tmp/bad" --quiet -- \
  "stages.excavate.scale_off" 'this stage runs until = "steps"' 'give until = "equilibrium"'
# After a drift study's reference stage, loose blocks are results (fallen), not scaled off.
"$py" - "$src/cases/drift/small.toml" "$tmp/drift.toml" <<'PY'
import sys
s = open(sys.argv[1]).read()
t = s.replace('name = "rest_1"\n', 'name = "rest_1"\nscale_off = "0.1 m"\n', 1)
assert t != s
open(sys.argv[2], "w").write(t.replace('file = "', 'file = "' + sys.argv[1].rsplit("/", 1)[0] + '/'))
PY
expect "scale_off after the drift's reference" 2 run "$tmp/drift.toml" --out "$tmp/bad" --quiet -- \
  "stages.rest_1.scale_off" "comes after the drift's reference stage ('excavate')" "counted as fallen"
[ -e "$tmp/bad" ] && { echo "FAIL a refused case made an output folder"; fail=1; }
exit $fail
