#!/usr/bin/env bash
# Restart: a run continued from the checkpoint written at the end of its first stage repeats the
# uninterrupted run exactly (same final state, bit for bit), and keeps the first run's history.
# Usage: bash run_restart.sh <rockdem-binary> <source-dir>
set -u
bin=$1
src=$2
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
fail=0
case_file="$src/cases/sliding_block/incline.toml"
"$bin" run "$case_file" --out "$tmp/full" --quiet || { echo "FAIL full run"; exit 1; }
cp -r "$tmp/full" "$tmp/restarted"
rm "$tmp/restarted/final_state.h5"
"$bin" run "$case_file" --out "$tmp/restarted" --restart "$tmp/full/stage_1_settle.h5" --quiet || { echo "FAIL restarted run"; exit 1; }
[ -f "$tmp/restarted/history.h5" ] && [ -f "$tmp/restarted/history_from_stage_2.h5" ] || { echo "FAIL histories not both kept"; fail=1; }
/usr/bin/python3 - "$tmp/full/final_state.h5" "$tmp/restarted/final_state.h5" <<'PY' || fail=1
import sys, h5py, numpy as np
a, b = (h5py.File(f, "r", locking=False) for f in sys.argv[1:3])
for name in ("gridpoints/x", "gridpoints/v", "blocks/xc", "blocks/vc", "contacts/state", "contacts/sigma_n"):
    if not np.array_equal(a[name][()], b[name][()]):
        print("FAIL restart differs in", name); sys.exit(1)
print("ok   restarted run ends in the same state, bit for bit (x_c = %s)" % a["blocks/xc"][()][1])
PY
# A checkpoint of another case is refused with a message.
out=$("$bin" run "$src/cases/direct_shear/test09_coulomb.toml" --out "$tmp/other" --restart "$tmp/full/stage_1_settle.h5" --quiet 2>&1)
code=$?
if [ $code -ne 2 ]; then echo "FAIL mismatched checkpoint: exit $code: $out"; fail=1; else echo "ok   mismatched checkpoint refused: $(head -c 200 <<<"$out")"; fi
exit $fail
