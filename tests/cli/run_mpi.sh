#!/usr/bin/env bash
# `rockdem run` must start and finish cleanly under mpirun on 1, 2 and 3 ranks (serial physics on
# rank 0 until domain decomposition lands; the other ranks wait) and give the same result.
# Usage: bash run_mpi.sh <rockdem-binary> <source-dir>
set -u
bin=$1
src=$2
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_rmaps_base_oversubscribe=1
fail=0
for np in 1 2 3; do
  out=$(timeout 300 mpirun -np $np "$bin" run "$src/cases/sliding_block/incline.toml" --out "$tmp/np$np" --quiet 2>&1)
  code=$?
  if [ $code -ne 0 ]; then echo "FAIL np=$np: exit $code: $out"; fail=1; continue; fi
  [ -f "$tmp/np$np/final_state.h5" ] || { echo "FAIL np=$np: no final_state.h5"; fail=1; continue; }
  echo "ok   np=$np"
done
# Bad input under mpirun: non-zero exit on every rank, message once.
sed 's/^friction = "20 deg"/friction = "95 deg"/' "$src/cases/sliding_block/incline.toml" > "$tmp/bad.toml"
out=$(timeout 120 mpirun -np 2 "$bin" run "$tmp/bad.toml" --out "$tmp/bad" --quiet 2>&1)
code=$?
n=$(grep -c "out of range" <<<"$out")
if [ $code -eq 0 ] || [ "$n" -ne 1 ]; then echo "FAIL bad input under mpirun: exit $code, $n messages: $out"; fail=1; else echo "ok   bad input under mpirun (exit $code)"; fi
# Same final state on 1 and 2 ranks (h5py from Debian's python3).
if /usr/bin/python3 -c "import h5py" 2>/dev/null; then
  /usr/bin/python3 - "$tmp/np1/history.h5" "$tmp/np2/history.h5" <<'PY' || fail=1
import sys, h5py, numpy as np
a, b = (h5py.File(f, "r")["history/block_x"][()] for f in sys.argv[1:3])
if a.shape != b.shape or not np.array_equal(a, b):
    print("FAIL histories differ between 1 and 2 ranks"); sys.exit(1)
print("ok   identical histories on 1 and 2 ranks (%d samples, x_end = %.6f m)" % (a.size, a[-1]))
PY
fi
exit $fail
