#!/usr/bin/env bash
# Side-by-side: rockdem vs LAMMPS (Debian package `lammps`, serial `lmp`, atom_style body
# rounded/polygon + pair_style body/rounded/polygon) on the same packing of rigid polygons, the
# same time step and step count, in one run: repetitions alternate rockdem, LAMMPS, rockdem, ...
# (so both see the same machine load), then the medians and the ratio rockdem/LAMMPS in
# contact-steps per second per core are printed. Both codes are single-process, single-thread.
#
#   scripts/bench/compare_lammps.sh [BUILD_DIR] [STEPS] [REPS]
#     BUILD_DIR  build tree with rockdem_bench_engine (default: build-bench; configured and
#                built if missing: cmake -S . -B BUILD_DIR -DCMAKE_BUILD_TYPE=Release)
#     STEPS      steps per run (default 2000); REPS repetitions each (default 3)
#
# Contact-steps per second for LAMMPS use rockdem's contact count on the same packing (LAMMPS
# does not report contact counts for body styles); both codes have two contact points per
# touching block pair here, so the ratio is the inverse ratio of the timed-loop times.
# Times: rockdem times Engine::run_steps; LAMMPS's "Loop time" of `run` (setup excluded in both).
set -euo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)
build=${1:-$root/build-bench}
steps=${2:-2000}
reps=${3:-3}
[[ $build = /* ]] || build=$root/$build
bench=$build/scripts/bench/rockdem_bench_engine
command -v lmp >/dev/null || { echo "lmp not found: apt-get install lammps" >&2; exit 1; }
lmp_help=$(lmp -h)
grep -q 'body/rounded/polygon' <<<"$lmp_help" || { echo "this lmp has no body/rounded/polygon pair style" >&2; exit 1; }
if [[ ! -x $bench ]]; then
  cmake -S "$root" -B "$build" -DCMAKE_BUILD_TYPE=Release >/dev/null
  cmake --build "$build" -j2 --target rockdem_bench_engine
fi
work=$(mktemp -d /tmp/rockdem-lammps.XXXXXX)
trap 'rm -rf "$work"' EXIT


echo "machine: $(lscpu | grep 'Model name' | sed 's/.*: *//'), $(nproc) cores; load: $(cut -d' ' -f1-3 /proc/loadavg)"
echo "date: $(date -u '+%Y-%m-%d %H:%M UTC')"
export OMP_NUM_THREADS=1
echo "lammps: $(grep -m1 'Large-scale' <<<"$lmp_help" | sed 's/.*Simulator - //')"
# Packing and LAMMPS input (one untimed rockdem repetition writes them)
"$bench" contacts --steps "$steps" --reps 1 --lammps "$work" | grep -v '^RESULT' | sed 's/^/  /'

rd=() lm=() lmcpu=() rdcpu=() contacts=
for ((r = 1; r <= reps; r++)); do
  line=$("$bench" contacts --steps "$steps" --reps 1 | grep '^RESULT')
  contacts=$(sed 's/.* touching=\([0-9]*\).*/\1/' <<<"$line")
  s=$(sed 's/.* seconds=\([0-9.e+-]*\).*/\1/' <<<"$line")
  c=$(sed 's/.* cpu_seconds=\([0-9.e+-]*\).*/\1/' <<<"$line")
  rd+=("$s") rdcpu+=("$c")
  lmp -in "$work/in.packing" -var steps "$steps" -log "$work/log.$r" >/dev/null
  ls=$(sed -n 's/^Loop time of \([0-9.e+-]*\) on 1 procs for .*/\1/p' "$work/log.$r")
  pct=$(sed -n 's/^\([0-9.]*\)% CPU use.*/\1/p' "$work/log.$r")
  lm+=("$ls") lmcpu+=("$(awk -v t="$ls" -v p="$pct" 'BEGIN{printf "%.6f", t*p/100}')")
  printf 'rep %d: rockdem %.3f s (cpu %.3f s), LAMMPS %.3f s (cpu %.3f s, %s%% CPU use)\n' \
    "$r" "$s" "$c" "$ls" "${lmcpu[-1]}" "$pct"
done
grep -A8 '^Section' "$work/log.$reps" | sed 's/^/  LAMMPS /'
echo "  LAMMPS last run, thermo (step, kinetic, potential energy [J/m]):"
sed -n '/^ *Step/,/^Loop time/p' "$work/log.$reps" | sed '$d' | sed 's/^/    /'

median() { printf '%s\n' "$@" | sort -g | awk '{a[NR]=$1} END{print (NR%2 ? a[(NR+1)/2] : (a[NR/2]+a[NR/2+1])/2)}'; }
mr=$(median "${rd[@]}") ml=$(median "${lm[@]}") mrc=$(median "${rdcpu[@]}") mlc=$(median "${lmcpu[@]}")
awk -v n="$contacts" -v s="$steps" -v r="$mr" -v l="$ml" -v rc="$mrc" -v lc="$mlc" 'BEGIN{
  printf "contacts (touching contact points, rockdem count on the same packing): %d; steps: %d\n", n, s
  printf "median wall time of the timed loop: rockdem %.3f s, LAMMPS %.3f s\n", r, l
  printf "rockdem: %.3e contact-steps/s per core (%.1f ns per contact-step)\n", n*s/r, 1e9*r/(n*s)
  printf "LAMMPS : %.3e contact-steps/s per core (%.1f ns per contact-step)\n", n*s/l, 1e9*l/(n*s)
  printf "ratio rockdem/LAMMPS (contact-steps/s, wall): %.2f\n", l/r
  printf "ratio rockdem/LAMMPS (contact-steps/s, cpu time): %.2f\n", lc/rc
}'
