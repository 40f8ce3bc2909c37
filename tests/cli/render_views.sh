#!/usr/bin/env bash
# scripts/render_views.py, the standard views of a run as PNG without ParaView or a display:
#  - on the rigid stack (tests/cli/render_views/stack.toml) the views are written and what they
#    show is the closed form: the rigid blocks' mean vertical stress 5.0130 and 5.0390 MPa (the top
#    load plus the weight above each centroid; the fixed base has none, drawn grey), contact normal
#    stresses 5.026 and 5.052 MPa; --time picks the nearest output, --out another folder;
#    --relative-to lower shows the joints' closures (0 .. 0.50520 mm);
#  - on a jointed rock mass (tests/cli/rock_mass/sample.toml: 73 blocks, hundreds of contacts in
#    all three states) the per-state counts add up to the contact file's points, and every PNG is
#    a picture with content (not blank);
#  - bad input is exit 2 naming what is wrong (no folder, no VTK output, a step not written), an
#    output folder that cannot be made exit 1.
# Usage: bash render_views.sh <rockdem-binary> <source-dir>
set -u
bin=$1
src=$2
py=/usr/bin/python3
script="$src/scripts/render_views.py"
source "$src/tests/cli/lib/expect.sh"
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
fail=0

# run_views NAME ARGS...: runs the script, keeps its output in $out and exit code in $code.
run_views() {
  local name=$1
  shift
  out=$("$py" "$script" "$@" 2>&1)
  code=$?
}

# pictures DIR: every standard PNG exists and shows something: the block views are mostly filled
# with the blocks' colours (more than a third of the picture not white), the contact-state view
# has points in the colour of a state that is present (elastic blue), the normal-stress view has
# coloured points (left of the colour bar; the outlines are grey).
pictures() {
  "$py" - "$1" <<'PY'
import sys
import matplotlib.image as mpimg
import numpy as np
bad, said = [], []
def load(f):
    im = mpimg.imread(f"{sys.argv[1]}/{f}")[..., :3]
    if im.dtype != np.float32 and im.dtype != np.float64:
        im = im / 255.0
    return im
for f in ["blocks_displacement.png", "blocks_stress.png"]:
    im = load(f)
    filled = float(np.mean(np.any(im < 0.95, axis=-1)))
    said.append(f"{f} {filled:.0%} filled")
    if filled < 0.2:
        bad.append(f"{f}: only {filled:.1%} of it is not white")
im = load("contacts_state.png")
blue = int(np.sum(np.all(np.abs(im - np.array([31, 119, 180]) / 255.0) < 0.06, axis=-1)))
said.append(f"contacts_state.png {blue} elastic-blue px")
if blue < 20:
    bad.append(f"contacts_state.png: {blue} pixels of the elastic colour")
im = load("contacts_normal_stress.png")
plot = im[:, : int(0.72 * im.shape[1])]  # left of the colour bar
colourful = int(np.sum(plot.max(axis=-1) - plot.min(axis=-1) > 0.3))
said.append(f"contacts_normal_stress.png {colourful} coloured px")
if colourful < 20:
    bad.append(f"contacts_normal_stress.png: {colourful} coloured pixels")
print("; ".join(bad) if bad else ", ".join(said))
sys.exit(1 if bad else 0)
PY
}

# --- the rigid stack: closed-form stresses in the views ---------------------------------------
if ! "$bin" run "$src/tests/cli/render_views/stack.toml" --out "$tmp/stack" --quiet --no-plots >"$tmp/stack.log" 2>&1; then
  echo "FAIL the stack case did not run: $(tail -5 "$tmp/stack.log")"
  exit 1
fi
run_views stack "$tmp/stack" --stress-component yy
if [ "$code" -ne 0 ]; then
  echo "FAIL stack views: exit $code: $out"
  fail=1
else
  r=$("$py" - "$out" <<'PY'
import re, sys
out = sys.argv[1]
rho_g = 2650 * 9.81
want_blocks = (5e6 + 0.5 * rho_g) / 1e6, (5e6 + 1.5 * rho_g) / 1e6
want_contacts = (5e6 + rho_g) / 1e6, (5e6 + 2 * rho_g) / 1e6
m = re.search(r"stress YY, compression positive \[MPa\]: ([-\d.e+]+) \.\. ([-\d.e+]+) MPa; 1 cells of held", out)
c = re.search(r"contacts_normal_stress.png: ([-\d.e+]+) \.\. ([-\d.e+]+) MPa", out)
s = re.search(r"6 contact points: 6 elastic, 0 slipping, 0 open", out)
ok = bool(m and c and s)
if ok:
    got_b, got_c = (float(m.group(1)), float(m.group(2))), (float(c.group(1)), float(c.group(2)))
    ok = all(abs(g - w) < 1e-3 * w for g, w in zip(got_b + got_c, want_blocks + want_contacts))
    print(f"block mean stress {got_b} MPa (closed form {want_blocks[0]:.4f}, {want_blocks[1]:.4f}), "
          f"contacts {got_c} MPa (closed form {want_contacts[0]:.4f}, {want_contacts[1]:.4f}), base grey, 6 elastic")
else:
    print("the views' summary lacks the stack's stresses, the grey base or the contact states")
sys.exit(0 if ok else 1)
PY
  )
  if [ $? -eq 0 ]; then echo "ok   stack views: $r"; else echo "FAIL stack views: $r: $out"; fail=1; fi
  if p=$(pictures "$tmp/stack/views"); then echo "ok   stack pictures: $p"; else echo "FAIL stack pictures: $p"; fail=1; fi
fi

run_views stack_time "$tmp/stack" --time 0 --out "$tmp/first"
if [ "$code" -eq 0 ] && grep -q "step 0, t = 0 s" <<<"$out" && [ -s "$tmp/first/blocks_stress.png" ]; then
  echo "ok   --time 0 --out: the first output drawn into another folder"
else
  echo "FAIL --time 0 --out: exit $code: $out"
  fail=1
fi

# Relative to the lower block's rigid motion: the lower block still, the upper one the upper
# joint's closure, the fixed base the lower joint's closure (5.0520e6 Pa / 10 GPa/m = 0.50520 mm).
run_views stack_relative "$tmp/stack" --relative-to lower --out "$tmp/relative"
if [ "$code" -eq 0 ] && r=$("$py" -c '
import re, sys
m = re.search(r"displacement relative to lower ([-\d.e+]+) \.\. ([-\d.e+]+) mm", sys.argv[1])
want = (5e6 + 2 * 2650 * 9.81) / 10e9 * 1e3
ok = bool(m) and abs(float(m.group(1))) < 1e-9 and abs(float(m.group(2)) - want) < 1e-3 * want
print(f"{m.group(0) if m else sys.argv[1]} (closed form 0 .. {want:.5f} mm)")
sys.exit(0 if ok else 1)' "$out"); then
  echo "ok   --relative-to: $r"
else
  echo "FAIL --relative-to: exit $code: ${r:-} $out"
  fail=1
fi

# --- a jointed rock mass: counts add up, pictures have content ---------------------------------
if ! "$bin" run "$src/tests/cli/rock_mass/sample.toml" --out "$tmp/mass" --quiet --no-plots >"$tmp/mass.log" 2>&1; then
  echo "FAIL the rock-mass sample did not run: $(tail -5 "$tmp/mass.log")"
  exit 1
fi
run_views mass "$tmp/mass"
if [ "$code" -ne 0 ]; then
  echo "FAIL rock-mass views: exit $code: $out"
  fail=1
else
  r=$("$py" - "$out" "$tmp/mass/vtk" <<'PY'
import glob, re, sys, vtk
out, vdir = sys.argv[1], sys.argv[2]
reader = vtk.vtkXMLPUnstructuredGridReader()
reader.SetFileName(sorted(glob.glob(vdir + "/contacts_*.pvtu"))[-1])
reader.Update()
n = reader.GetOutput().GetNumberOfPoints()
m = re.search(r"(\d+) contact points: (\d+) elastic, (\d+) slipping, (\d+) open", out)
ok = bool(m) and int(m.group(1)) == n and sum(int(m.group(k)) for k in (2, 3, 4)) == n and n > 100
print(f"{m.group(0) if m else 'no contact counts'}; the last contacts file has {n} points")
sys.exit(0 if ok else 1)
PY
  )
  if [ $? -eq 0 ]; then echo "ok   rock-mass views: $r"; else echo "FAIL rock-mass views: $r"; fail=1; fi
  if p=$(pictures "$tmp/mass/views"); then echo "ok   rock-mass pictures: $p"; else echo "FAIL rock-mass pictures: $p"; fail=1; fi
fi

# --- bad input ----------------------------------------------------------------------------------
# bad NAME CODE ARGS... -- SUBSTRINGS...: lib/expect.sh's check with the script as the command.
bad() { bin="$py" expect "$1" "$2" "$script" "${@:3}"; }
mkdir -p "$tmp/empty"
touch "$tmp/a_file"
bad no_folder 2 "$tmp/nowhere" -- "nowhere' is not a folder"
bad no_vtk 2 "$tmp/empty" -- "has no vtk/blocks.pvd" "vtk_interval = 0"
bad step_not_written 2 "$tmp/stack" --step 7 -- "--step 7" "no output at that step" "written steps"
bad out_is_a_file 1 "$tmp/stack" --out "$tmp/a_file/views" -- "cannot create"
bad relative_to_unknown 2 "$tmp/stack" --relative-to lowr --out "$tmp/v3" -- "no block or group 'lowr'" "did you mean 'lower'?"

exit $fail
