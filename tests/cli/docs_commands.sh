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
