#!/usr/bin/env bash
# `rockdem run --threads N` gives the results of one thread, bit for bit (docs/parallel.md,
# "Threads"): the final state and every history of a case run on 1, 2 and 3 threads, serially and
# as 2 processes of 2 threads each (against 2 processes of one thread: the histories summed over
# processes are added in process order either way). Cases: deformable blocks with an in-situ
# stress and an excavation, rigid blocks falling metres, the direct-shear specimen, an earthquake
# through a compliant base with free-field sides. Also: the warning when a process may use fewer
# cores than it has threads, and bad --threads values.
# Usage: bash threads.sh <rockdem-binary> <source-dir>
set -u
bin=$1
src=$2
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_rmaps_base_oversubscribe=1
fail=0
py=/usr/bin/python3

same() {  # A B: every dataset of history.h5 and final_state.h5 equal, bit for bit
  "$py" - "$1" "$2" <<'PY'
import sys, h5py, numpy as np
a, b = sys.argv[1:3]
n, bad = 0, []
for name in ("history.h5", "final_state.h5"):
    A, B = h5py.File(f"{a}/{name}", "r"), h5py.File(f"{b}/{name}", "r")
    keys = []
    A.visititems(lambda k, o: keys.append(k) if isinstance(o, h5py.Dataset) else None)
    for k in keys:
        n += 1
        if k not in B:
            bad.append(f"{name}:{k} missing"); continue
        x, y = A[k][()], B[k][()]
        if x.shape != y.shape or not np.array_equal(x, y, equal_nan=getattr(x, "dtype", None) is not None and x.dtype.kind == "f"):
            bad.append(f"{name}:{k} differs")
if n < 10: bad.append(f"only {n} datasets")
if bad:
    print("  " + "\n  ".join(bad[:10])); sys.exit(1)
print(f"{n} datasets identical")
PY
}

run() {  # out, args...: a run that must succeed
  local out=$1; shift
  if ! timeout 600 "$@" --out "$tmp/$out" --quiet >"$tmp/$out.log" 2>&1; then
    echo "FAIL $out: exit $?"; tail -5 "$tmp/$out.log"; fail=1; return 1
  fi
}

check_case() {  # name, case args...
  local name=$1; shift
  run "$name-t1" "$bin" run "$@" || return
  for t in 2 3; do
    run "$name-t$t" "$bin" run "$@" --threads $t || continue
    if r=$(same "$tmp/$name-t1" "$tmp/$name-t$t"); then echo "ok   $name on $t threads: $r"
    else echo "FAIL $name on $t threads:"; echo "$r"; fail=1; fi
  done
  run "$name-p2" mpirun -np 2 "$bin" run "$@" || return
  run "$name-p2t2" mpirun -np 2 --bind-to none "$bin" run "$@" --threads 2 || return
  if r=$(same "$tmp/$name-p2" "$tmp/$name-p2t2"); then echo "ok   $name on 2 processes of 2 threads: $r"
  else echo "FAIL $name on 2 processes of 2 threads:"; echo "$r"; fail=1; fi
}

check_case rock_mass "$src/tests/cli/parallel/rock_mass.toml"      # deformable blocks, in-situ stress, excavation
check_case collapse "$src/tests/cli/parallel/collapse.toml"        # rigid blocks falling metres
check_case direct_shear "$src/cases/direct_shear/test09_mohr_coulomb.toml" --stages 1
check_case free_field "$src/cases/verification/free_field/column.toml" --no-plots

# More threads than the cores the process may use: said, and the run goes on.
if command -v taskset >/dev/null; then
  if taskset -c 0 "$bin" run "$src/tests/cli/parallel/collapse.toml" --threads 2 --out "$tmp/pinned" --quiet >"$tmp/pinned.log" 2>&1 &&
     grep -q -- "--threads 2: this process may use 1 core" "$tmp/pinned.log"; then
    echo "ok   a process pinned to one core with 2 threads is warned"
  else
    echo "FAIL no warning for 2 threads on one core:"; cat "$tmp/pinned.log"; fail=1
  fi
fi

# Bad values: a usage error (exit 2) that names the option and its range, and no folder.
. "$src/tests/cli/lib/expect.sh"
for bad in 0 -2 300 two 1.5; do
  expect "--threads $bad" 2 run "$src/tests/cli/parallel/collapse.toml" --threads "$bad" --out "$tmp/bad" --quiet -- \
    "--threads" "not in range 1 to 256"
  [ -e "$tmp/bad" ] && { echo "FAIL --threads $bad made a folder"; fail=1; }
done
exit $fail
