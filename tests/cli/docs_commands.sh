#!/usr/bin/env bash
# The README's and the tutorials' command blocks run as written (docs/reliability.md): every ```sh
# and ```python block, in a folder laid out like a clone after the build (build/rockdem, scripts/,
# cases/), must exit 0 and write the files its commands name as outputs. The README's two
# commands are not run here (the stop check and CI run them); scripts/run-lab-dem runs one case
# instead of 21; the tutorial's `scripts/build` after adding an effect is mirrored by rockdem built
# with the effect's listing taken from the page (rockdem_tutorial, tests/CMakeLists.txt).
# Usage: bash docs_commands.sh <rockdem-binary> <source-dir>
set -u
bin=$1
src=$2
tutorial_bin="$(dirname "$bin")/rockdem_tutorial"
[ -x "$tutorial_bin" ] || { echo "FAIL no $tutorial_bin (built with rockdem by tests/CMakeLists.txt)"; exit 1; }
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_rmaps_base_oversubscribe=1
w="$tmp/clone"
mkdir -p "$w/build"
ln -s "$bin" "$w/build/rockdem"
cp -r "$src/scripts" "$w/scripts"
ln -s "$src/cases" "$w/cases"
export ROCKDEM_BIN="$w/build/rockdem"  # the scripts use it instead of building
# The README's Python example reads the history of `scripts/demo --dem`, which runs this:
(cd "$w" && build/rockdem run --default --out rockdem-output/default --quiet) || { echo "FAIL run --default"; exit 1; }
/usr/bin/python3 "$src/tests/cli/docs/run_doc_commands.py" "$w" "$tutorial_bin" "$src/README.md" "$src"/docs/tutorials/*.md
rc=$?
# The README's quoted ladder (Mohr-Coulomb on test 9's twin with its case, as scripts/demo runs
# it) against today's: a figure in the README must be the one its command gives (3 digits).
# (rockdem itself: the tutorial's steps above leave build/rockdem with its own effect compiled in.)
(cd "$w" && "$bin" diagnose --data cases/direct_shear/twins/test09.csv --law mohr_coulomb \
  --case cases/direct_shear/test09_mohr_coulomb.toml --json "$tmp/readme_ladder.json" --quiet) >/dev/null 2>&1 ||
  { echo "FAIL the README's ladder: diagnose failed"; exit 1; }
/usr/bin/python3 - "$src/README.md" "$tmp/readme_ladder.json" <<'PY' || rc=1
import json, re, sys
text = open(sys.argv[1], encoding="utf-8").read().replace("\n", " ")
m = re.search(r"Mohr-Coulomb: combined NRMSE ([0-9.]+) → ([0-9.]+) with\s+`(\w+)`", text)
if not m:
    sys.exit("FAIL the README's ladder sentence ('Mohr-Coulomb: combined NRMSE A → B with `effect`') was not found")
ladder = json.load(open(sys.argv[2]))["ladder"]
got = (f"{ladder[0]['nrmse']['combined']:.3f}", f"{ladder[-1]['nrmse']['combined']:.3f}", "+".join(ladder[-1]["effects"]))
if got != m.groups():
    sys.exit(f"FAIL the README quotes the ladder {m.groups()}, diagnose gives {got}")
print(f"ok   the README's ladder {got[0]} -> {got[1]} with {got[2]}")
PY
exit $rc
