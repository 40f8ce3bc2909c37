#!/usr/bin/env bash
# Timings of the laboratory-test cases for docs/performance.md:
#  1. element runs of all 21 cases (in-process time as `rockdem element` prints it, and wall time
#     of the 21 processes);
#  2. the DEM run of test 9 (Mohr-Coulomb, all three stages) at the report's 100 mm/s and at the
#     laboratory rate with mass scaling, side by side in one run of this script.
# Usage: scripts/bench/lab-cases.sh [BUILD_DIR]   (default build/)
set -euo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)
bin=${1:-$root/build}/rockdem
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
echo "# element runs (21 cases)"
total=0
t0=$(date +%s%N)
for t in 07 08 09 10 11 14 24; do
  for law in mohr_coulomb barton_bandis continuously_yielding; do
    line=$("$bin" element "$root/cases/direct_shear/test${t}_${law}.toml" --out "$tmp/e.csv" --overwrite | head -1)
    ms=$(sed -E 's/.* in ([0-9.]+) ms.*/\1/' <<<"$line")
    printf '  test%s %-22s %8s ms\n' "$t" "$law" "$ms"
    total=$(awk -v a="$total" -v b="$ms" 'BEGIN{print a+b}')
  done
done
wall=$(( ($(date +%s%N) - t0) / 1000000 ))
echo "  sum of in-process times: $total ms; wall time of the 21 processes (start-up, CSV writing included): $wall ms"
echo "# DEM, test 9 Mohr-Coulomb, 3 stages"
for mode in report lab; do
  if [[ $mode == report ]]; then opts=(); else opts=(--shear-velocity lab --mass-scaling-dt "1.2 ms"); fi
  t0=$(date +%s%N)
  "$bin" run "$root/cases/direct_shear/test09_mohr_coulomb.toml" --out "$tmp/$mode" --quiet "${opts[@]}"
  ms=$(( ($(date +%s%N) - t0) / 1000000 ))
  steps=$(/usr/bin/python3 -c "import h5py,sys; f=h5py.File(sys.argv[1],'r'); print(int(f['history/step'][-1]) if 'step' in f['history'] else -1)" "$tmp/$mode/history.h5" 2>/dev/null || echo "?")
  echo "  $mode rate: $((ms / 1000)).$(((ms % 1000) / 100)) s wall, steps $steps"
done
