#!/usr/bin/env bash
# The rock-mass example (cases/rock_mass/drift.toml): the generator builds it, it starts in
# equilibrium with its in-situ stress, the drift is excavated and the rock mass comes back to
# equilibrium; the summary script reads its final state. Checks: exit 0, both stages converged,
# the drift block is gone, the crown moved down and the springline inward by millimetres (not
# metres), the largest overlap stays within twice the largest elastic closure.
# Usage: bash rock_mass_example.sh <rockdem-binary> <source-dir>
set -u
bin=$1
src=$2
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
"$bin" run "$src/cases/rock_mass/drift.toml" --out "$tmp/out" --quiet || { echo "FAIL run exited $?"; exit 1; }
summary=$("$src/scripts/rock-mass-summary" "$tmp/out") || { echo "FAIL summary: $summary"; exit 1; }
echo "$summary"
PYTHONPATH="$src/tests/cli/lib" /usr/bin/python3 - "$tmp/out" <<'PY'
import sys, h5py, re
from checks import check, done
out = sys.argv[1]
with h5py.File(out + "/history.h5", "r", locking=False) as f:
    h = f["history"]
    stage, ratio = h["stage"][:], h["ratio"][:]
    crown, spring = h["crown_y"][-1], h["springline_x"][-1]
with h5py.File(out + "/final_state.h5", "r", locking=False) as f:
    names = [n.decode() if isinstance(n, bytes) else str(n) for n in f["blocks/name"][:]]
    over = f["contacts/overlap"][:]
    # Contacts that carry load (a contact of zero length carries none, whatever its state says).
    closed = (f["contacts/sigma_n"][:] > 0) & (f["contacts/length"][:] > 0)
    elastic = f["contacts/sigma_n"][:] / f["contacts/kn"][:].clip(1e-300)
check(stage[-1] == 2 and ratio[-1] < 1e-4, f"both stages ran and the last converged (ratio {ratio[-1]:.3g})")
check(not any(n.startswith("drift") for n in names), "the drift block was excavated")
check(-0.02 < crown < -1e-4, f"the crown moved down by millimetres ({crown * 1e3:.3f} mm)")
check(-0.02 < spring < -1e-4, f"the springline moved inward by millimetres ({spring * 1e3:.3f} mm)")
check(over[closed].max() < 2 * elastic[closed].max(), f"largest overlap {over[closed].max() * 1e3:.3f} mm within twice the largest elastic closure {elastic[closed].max() * 1e3:.3f} mm")
done()
PY
