#!/usr/bin/env bash
# Domain-decomposed runs give the serial run's results (docs/parallel.md). Each case runs serially
# and under mpirun on 2, 3 and 4 processes; the final state (every gridpoint, zone, block and
# contact, with its joint-law state) and the histories must be identical to the serial run's,
# bit for bit, except the histories that sum over the processes (unbalanced ratio, kinetic
# energy), which may differ in the last digits (relative 1e-12) because the partial sums are
# added in another order. The cases: a collapsing jointed face, an excavation in deformable
# jointed rock, the direct-shear specimen, two blocks (more processes than blocks) and an
# earthquake through a compliant base with free-field sides (held reactions, energy balance). Also: a restart from a checkpoint of a 2-process run on 3 processes
# (at a stage end, and within the free-field earthquake),
# blocks changing owner within a run (shared out again, moved to the process they touch; also
# under local damping), bad
# input under mpirun, and the case of more processes than blocks.
# Usage: bash parallel_equivalence.sh <rockdem-binary> <source-dir>
set -u
bin=$1
src=$2
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_rmaps_base_oversubscribe=1
fail=0
py=/usr/bin/python3

# compare A B: every dataset of history.h5 and final_state.h5.
compare() {
  "$py" - "$1" "$2" <<'PY'
import sys, h5py, numpy as np
a, b = sys.argv[1:3]
summed = {"history/ratio", "history/kinetic", "history/unbalanced_ratio"}
# the same in the checkpoint (its histories so far, and the engine's last ratios and energy terms)
summed |= {"arrays/" + k.replace("/", ".") for k in summed} | {"arrays/engine.step_values", "arrays/energy.terms"}
# and what the caller names (EXTRA_SUMMED: dataset name prefixes, e.g. a case's energy histories)
import os
summed_prefixes = tuple(os.environ.get("EXTRA_SUMMED", "").split())
worst, n, bad = 0.0, 0, []
for name in ("history.h5", "final_state.h5"):
    A, B = h5py.File(f"{a}/{name}", "r"), h5py.File(f"{b}/{name}", "r")
    keys = []
    A.visititems(lambda k, o: keys.append(k) if isinstance(o, h5py.Dataset) else None)
    for k in keys:
        if k not in B:
            bad.append(f"{name}:{k} missing"); continue
        x, y = A[k][()], B[k][()]
        n += 1
        if x.shape != y.shape:
            bad.append(f"{name}:{k} shape {x.shape} vs {y.shape}"); continue
        if (k in summed or (summed_prefixes and k.startswith(summed_prefixes))) and x.dtype.kind == "f":
            scale = np.nanmax(np.abs(x)) if x.size else 0.0
            rel = float(np.nanmax(np.abs(x - y)) / scale) if scale > 0 else 0.0
            worst = max(worst, rel)
            if not rel <= 1e-12: bad.append(f"{name}:{k} differs by {rel:.3g} relative")
        elif not np.array_equal(x, y, equal_nan=x.dtype.kind == "f"):
            bad.append(f"{name}:{k} differs")
if bad:
    print("  " + "\n  ".join(bad[:10])); sys.exit(1)
print(f"{n} datasets identical (summed histories within {worst:.1e})")
PY
}

run_case() {  # name, case args..., out: serial then 2-4 processes
  local name=$1; shift
  timeout 600 "$bin" run "$@" --out "$tmp/$name-1" --quiet >"$tmp/$name-1.log" 2>&1 || {
    echo "FAIL $name serial: exit $?"; cat "$tmp/$name-1.log"; fail=1; return; }
  for np in 2 3 4; do
    if ! timeout 600 mpirun -np $np "$bin" run "$@" --out "$tmp/$name-$np" --quiet >"$tmp/$name-$np.log" 2>&1; then
      echo "FAIL $name on $np processes: exit $?"; tail -5 "$tmp/$name-$np.log"; fail=1; continue
    fi
    if r=$(compare "$tmp/$name-1" "$tmp/$name-$np"); then echo "ok   $name on $np processes: $r"
    else echo "FAIL $name on $np processes:"; echo "$r"; fail=1; fi
  done
}

run_case collapse "$src/tests/cli/parallel/collapse.toml"        # rigid blocks falling metres
run_case rock_mass "$src/tests/cli/parallel/rock_mass.toml"      # deformable blocks, in-situ stress, excavation
run_case direct_shear "$src/cases/direct_shear/test09_mohr_coulomb.toml" --stages 1   # the direct-shear specimen
run_case incline "$src/cases/sliding_block/incline.toml"         # two blocks: more processes than blocks
run_case free_field "$src/cases/verification/free_field/column.toml" --no-plots   # earthquake: compliant base, free field, energy

# The VTK fields: one piece per process, written by that process, their .pvtu read as ParaView
# reads it: the serial run's cells and contacts, each with the process that computed it.
if "$py" -c "import vtk" 2>/dev/null; then
  if r=$("$py" - "$tmp/collapse-1/vtk" "$tmp/collapse-3/vtk" <<'PY'
import sys, glob, os, vtk
from vtk.util.numpy_support import vtk_to_numpy
def last(d, which):
    r = vtk.vtkXMLPUnstructuredGridReader()
    r.SetFileName(sorted(glob.glob(d + "/" + which + "_*.pvtu"))[-1])
    r.Update()
    return r.GetOutput()
serial, three = sys.argv[1], sys.argv[2]
ok = True
for which, data in (("blocks", "GetCellData"), ("contacts", "GetPointData")):
    a, b = last(serial, which), last(three, which)
    p = sorted(set(vtk_to_numpy(getattr(b, data)().GetArray("process")).tolist()))
    pieces = len(glob.glob(three + "/" + which + "_*_[0-9].vtu")) // len(glob.glob(three + "/" + which + "_*.pvtu"))
    same = (a.GetNumberOfCells(), a.GetNumberOfPoints()) == (b.GetNumberOfCells(), b.GetNumberOfPoints())
    print(f"{which}: processes {p}, {pieces} pieces per step, {b.GetNumberOfCells()} cells as in the serial run: {same}")
    ok = ok and p == [0, 1, 2] and pieces == 3 and same
sys.exit(0 if ok else 1)
PY
  ); then echo "ok   VTK pieces per process: $r"; else echo "FAIL VTK pieces: $r"; fail=1; fi
fi

# A restart on another process count: the checkpoint of the 2-process run's first stage,
# continued on 3 processes, ends where the uninterrupted serial run ends, with its whole history.
cp -r "$tmp/rock_mass-2" "$tmp/restart"
if timeout 600 mpirun -np 3 "$bin" run "$src/tests/cli/parallel/rock_mass.toml" --out "$tmp/restart" --quiet \
     --restart "$tmp/restart/stage_1_in_situ.h5" >"$tmp/restart.log" 2>&1; then
  if r=$(compare "$tmp/rock_mass-1" "$tmp/restart")
  then echo "ok   restart of a 2-process checkpoint on 3 processes (history and final state): $r"
  else echo "FAIL restart on 3 processes:"; echo "$r"; fail=1; fi
else
  echo "FAIL restart on 3 processes: exit $?"; tail -5 "$tmp/restart.log"; fail=1
fi

# A restart within a stage on another process count: the free-field earthquake on 2 processes
# with checkpoints during the shaking (they change nothing), continued on 3 processes from one of
# them, ends where the uninterrupted serial run ends (the columns' motion and clock, the held
# reactions, the energy terms and the damping state all come back).
ff="$src/cases/verification/free_field/column.toml"
if timeout 600 mpirun -np 2 "$bin" run "$ff" --out "$tmp/ffck" --quiet --no-plots --checkpoint-every "5000 steps" >"$tmp/ffck.log" 2>&1; then
  if r=$(compare "$tmp/free_field-1" "$tmp/ffck"); then echo "ok   free field on 2 processes with checkpoints within the shaking: $r"
  else echo "FAIL free field with checkpoints:"; echo "$r"; fail=1; fi
  k=$(ls "$tmp/ffck" | grep '^checkpoint_step_' | sort -t_ -k3 -n | head -1)
  if [ -n "$k" ] && timeout 600 mpirun -np 3 "$bin" run "$ff" --out "$tmp/ffck" --quiet --no-plots --restart "$tmp/ffck/$k" >"$tmp/ffr.log" 2>&1 &&
     r=$(compare "$tmp/free_field-1" "$tmp/ffck"); then echo "ok   restart within the shaking ($k of a 2-process run) on 3 processes: $r"
  else echo "FAIL restart within the shaking on 3 processes ($k):"; echo "${r:-}"; tail -5 "$tmp/ffr.log"; fail=1; fi
else
  echo "FAIL free field with checkpoints on 2 processes: exit $?"; tail -5 "$tmp/ffck.log"; fail=1
fi

# Blocks changing owner within a run (Engine::rebalance; the runs above may change some too): a
# variant of the rock mass with a large opening on one side and weaker joints, whose excavation
# and loosening leave the processes out of balance (--imbalance-limit 1.02: the blocks are shared
# out again with METIS at the excavation and again as blocks loosen, deformable blocks with
# their zones, contacts and energy balance; leaving the balance's state behind fails this),
# and the collapse, whose falling blocks land among another process's blocks (they move to it).
# Each gives the serial run's results; with --imbalance-limit 0 nothing is shared out again.
sed -e 's/centre = \["0 m", "0 m"\]/centre = ["2.8 m", "0.5 m"]/' -e 's/radius = "0.8 m"/radius = "2.6 m"/' \
    -e 's/^steps = 3000/steps = 10000/' -e 's/friction = "15 deg"/friction = "5 deg"/' \
    "$src/tests/cli/parallel/rock_mass.toml" > "$tmp/loosening.toml"
printf '\n[[histories]]\nname = "energy_strain"\nquantity = "energy"\ncomponent = "strain"\n\n[[histories]]\nname = "energy_error"\nquantity = "energy_balance_error"\n' >> "$tmp/loosening.toml"
grep -q 'radius = "2.6 m"' "$tmp/loosening.toml" && grep -q '^steps = 10000' "$tmp/loosening.toml" || { echo "FAIL the loosening variant was not made"; fail=1; }
owners() {  # name, process count, log pattern wanted (or "none:" + pattern refused), run args...
  local name=$1 np=$2 want=$3; shift 3
  if ! timeout 600 mpirun -np "$np" "$bin" run "$@" --out "$tmp/$name" --no-plots >"$tmp/$name.log" 2>&1; then
    echo "FAIL $name: exit $?"; tail -5 "$tmp/$name.log"; fail=1; return 1; fi
  if [ "${want#none:}" != "$want" ]; then
    if grep -q "${want#none:}" "$tmp/$name.log"; then echo "FAIL $name: '${want#none:}' in its log"; fail=1; return 1; fi
  elif ! grep -q "$want" "$tmp/$name.log"; then
    echo "FAIL $name: no '$want' in its log:"; grep -i "moved\|ownership" "$tmp/$name.log"; fail=1; return 1
  fi
}
# Its energy histories and the balance's scale are sums over the processes: the last digits may differ.
energy_sums="history/energy arrays/history.energy arrays/energy.scale"
if timeout 600 "$bin" run "$tmp/loosening.toml" --out "$tmp/loosening-1" --quiet --no-plots >"$tmp/loosening-1.log" 2>&1; then
  for np in 2 3; do
    # at the excavation, and again at least once as the blocks loosen
    if owners loosening-$np $np "blocks shared out again (METIS" "$tmp/loosening.toml" --imbalance-limit 1.02 &&
       [ "$(grep -c 'shared out again' "$tmp/loosening-$np.log")" -ge 2 ] &&
       r=$(EXTRA_SUMMED="$energy_sums" compare "$tmp/loosening-1" "$tmp/loosening-$np"); then
      echo "ok   blocks shared out again on $np processes ($(grep -c 'shared out again' "$tmp/loosening-$np.log") times): $r"
    else echo "FAIL blocks shared out again on $np processes: ${r:-}"; fail=1; fi
    r=
  done
  if owners loosening-never 3 "none:shared out again" "$tmp/loosening.toml" --imbalance-limit 0 &&
     r=$(EXTRA_SUMMED="$energy_sums" compare "$tmp/loosening-1" "$tmp/loosening-never"); then echo "ok   --imbalance-limit 0 shares nothing out again: $r"
  else echo "FAIL --imbalance-limit 0: ${r:-}"; fail=1; fi
else
  echo "FAIL loosening serial: exit $?"; tail -5 "$tmp/loosening-1.log"; fail=1
fi
r=
if owners collapse-strays 3 "moved to the process whose blocks" "$src/tests/cli/parallel/collapse.toml" &&
   r=$(compare "$tmp/collapse-1" "$tmp/collapse-strays"); then
  echo "ok   fallen blocks moved to the process they touch ($(grep -c 'moved to the process' "$tmp/collapse-strays.log") times): $r"
else echo "FAIL fallen blocks moved: ${r:-}"; fail=1; fi
# The same under local damping, whose running averages of each block's velocity only the owner
# keeps: they go with a block that changes owner (on 3 processes, shared out again and a stray
# moved, both within the stage; leaving the averages behind fails this).
r=
sed 's/^damping = "none"/damping = "local"/' "$src/tests/cli/parallel/collapse.toml" > "$tmp/collapse_local.toml"
if grep -q '^damping = "local"' "$tmp/collapse_local.toml" &&
   timeout 600 "$bin" run "$tmp/collapse_local.toml" --out "$tmp/collapse_local-1" --quiet --no-plots >"$tmp/collapse_local-1.log" 2>&1 &&
   owners collapse_local-3 3 "moved to the process whose blocks" "$tmp/collapse_local.toml" &&
   r=$(compare "$tmp/collapse_local-1" "$tmp/collapse_local-3"); then
  echo "ok   under local damping, blocks change owner on 3 processes ($(grep -c '^step [0-9]*: .*moved' "$tmp/collapse_local-3.log") changes): $r"
else echo "FAIL blocks changing owner under local damping: ${r:-}"; fail=1; fi
# Progress under mpirun: Open MPI gives each process a pseudo-terminal whatever mpirun's own
# output is, so a log must not take the line that updates in place (carriage returns and erase
# codes); each progress line is a line of its own.
sed 's/^\[output\]$/[output]\nprogress_seconds = "0.5 s"/' "$src/tests/cli/parallel/collapse.toml" > "$tmp/progress.toml"
if grep -q '^progress_seconds' "$tmp/progress.toml" &&
   timeout 600 mpirun -np 2 "$bin" run "$tmp/progress.toml" --out "$tmp/progress" --no-plots >"$tmp/progress.log" 2>&1; then
  lines=$(grep -c '^  [^ ].* step [0-9]* *t = ' "$tmp/progress.log")
  if [ "$lines" -ge 2 ] && ! grep -q $'\r\|\x1b' "$tmp/progress.log"; then echo "ok   progress under mpirun: $lines lines, no carriage return or escape code"
  else echo "FAIL progress under mpirun: $lines progress lines; carriage returns or escape codes: $(grep -c $'\r\|\x1b' "$tmp/progress.log")"; fail=1; fi
else echo "FAIL progress run under mpirun: exit $?"; tail -5 "$tmp/progress.log"; fail=1; fi

. "$src/tests/cli/lib/expect.sh"
for bad in 0.5 two 101 1.2x; do
  expect "--imbalance-limit $bad" 2 run "$src/tests/cli/parallel/collapse.toml" --imbalance-limit "$bad" --out "$tmp/bad-limit" --quiet -- \
    "--imbalance-limit" "give a factor from 1 to 100"
  [ -e "$tmp/bad-limit" ] && { echo "FAIL --imbalance-limit $bad made a folder"; fail=1; }
done

# Bad input under mpirun: non-zero exit, the message once.
sed 's/^friction = "20 deg"/friction = "95 deg"/' "$src/cases/sliding_block/incline.toml" > "$tmp/bad.toml"
out=$(timeout 120 mpirun -np 2 "$bin" run "$tmp/bad.toml" --out "$tmp/bad" --quiet 2>&1)
code=$?
n=$(grep -c "out of range" <<<"$out")
if [ $code -eq 0 ] || [ "$n" -ne 1 ]; then echo "FAIL bad input under mpirun: exit $code, $n messages: $out"; fail=1
else echo "ok   bad input under mpirun (exit $code, one message)"; fi

# An output folder that is refused on process 0 stops every process (none is left waiting).
out=$(timeout 120 mpirun -np 2 "$bin" run "$src/cases/sliding_block/incline.toml" --out "$tmp/incline-2" --quiet 2>&1)
code=$?
if [ $code -ne 2 ] || ! grep -q "not empty" <<<"$out"; then echo "FAIL refused folder under mpirun: exit $code: $out"; fail=1
else echo "ok   a refused output folder stops every process (exit 2)"; fi
exit $fail
