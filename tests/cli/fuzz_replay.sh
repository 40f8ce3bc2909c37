#!/usr/bin/env bash
# The parser replay (tests/fuzz/replay.py): a fixed, seeded corpus of mutated inputs (case TOML,
# rock-mass tables, laboratory-test and element cases, measurement CSV, accelerogram, calibration
# JSON named by a case) through the commands that read them. Every input must end within 60 s,
# without a signal, with exit 0 or 2, and every exit 2 must name the input file. 60 mutations per
# seed input here (420 in all, about 30 s); docs/reliability.md gives the larger runs.
# Usage: bash fuzz_replay.sh <rockdem-binary> <source-dir>
set -u
bin=$1
src=$2
exec /usr/bin/python3 "$src/tests/fuzz/replay.py" "$bin" "$src" --per-target 60
