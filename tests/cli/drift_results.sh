#!/usr/bin/env bash
# The drift-study results ([drift], docs/drift-study.md) on tests/cli/drift/results.toml: an
# excavation in a small jointed rock mass and two stages after it. Checks:
#  - one row per stage from the reference on, the reference row all zeros (ratios 1);
#  - the crown and springline displacements in events.csv are the histories' displacement_at at
#    the same wall points (to 0.05 mm: the nearest gridpoint against a point on the wall);
#  - the per-set slip and opening maxima and the permeability tensor follow from the contacts
#    written beside them (the tensor recomputed here from the apertures: Snow's parallel plates);
#  - fallen blocks: none at the case's 2 cm; with a threshold of 0.1 mm the blocks that are that
#    far towards the opening at the last stage's end are listed, with the stage since which they
#    have been (a block back within it is no longer counted);
#  - the same as VTK fields: joints_/blocks_<n>_<stage>.vtu and their .pvd collections, the joint
#    fields equal to the CSV;
#  - a restart from the middle stage's checkpoint gives the same files; 2 processes too;
#  - bad [drift] input is refused naming the key.
# Usage: bash drift_results.sh <rockdem-binary> <source-dir>
set -u
bin=$1
src=$2
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_rmaps_base_oversubscribe=1
fail=0
case_file=$src/tests/cli/drift/results.toml
ok() { echo "ok   $1"; }
bad() { echo "FAIL $1"; fail=1; }

"$bin" run "$case_file" --out "$tmp/a" --quiet || { echo "FAIL run exited $?"; exit 1; }
PYTHONPATH="$src/tests/cli/lib" /usr/bin/python3 - "$tmp/a" <<'PY' || fail=1
import sys, csv, h5py, numpy as np
out = sys.argv[1]
from checks import check, done, rows
ev = rows(out + "/drift/events.csv")
check([r["name"] for r in ev] == ["excavate", "loosen", "settle"] and [r["kind"] for r in ev] == ["reference", "rest", "rest"],
      "events.csv: a row for the reference stage and each stage after it")
ref = ev[0]
check(all(float(v) == 0.0 for k, v in ref.items() if k.endswith("_m") or k in ("fallen_blocks", "loosened_contacts")),
      "the reference row is all zeros")
check(float(ref["k_xx_ratio"]) == 1.0 and float(ref["k_yy_ratio"]) == 1.0, "its permeability ratios are 1")
# Wall displacements against the histories at the same points (crown (0, 0.8), springline (0.8, 0)).
with h5py.File(out + "/history.h5", "r", locking=False) as f:
    h = f["history"]
    stage = h["stage"][:]
    series = {k: h[k][:] for k in ("crown_y", "springline_x")}
moved = {k: v[-1] - v[stage == 2][-1] for k, v in series.items()}
last = ev[-1]
# events.csv measures in the frame of the far field (its mean displacement, frame_x/y_m).
frame = {"crown_y": float(last["frame_y_m"]), "springline_x": float(last["frame_x_m"])}
for col, hist, sign in (("crown_inward_m", "crown_y", -1), ("right_springline_inward_m", "springline_x", -1)):
    expect = sign * (moved[hist] - frame[hist])
    check(abs(float(last[col]) - expect) < 5e-5,
          f"{col}: {float(last[col]) * 1e3:.4f} mm, the history {hist} less the frame's {expect * 1e3:.4f} mm")
check(0 < float(last["crown_inward_m"]) < 0.01, "the crown moved down, by less than a centimetre")
# The maxima per set and the permeability from the contacts of the last stage.
ct = rows(out + "/drift/contacts_4_settle.csv")
near = 1.6
area = np.pi * ((0.789732252 + near) ** 2 - 0.789732252 ** 2)
for s in ("steep", "flat"):
    sl = [abs(float(c["slip_m"])) for c in ct if c["set"] == s and float(c["distance_to_wall_m"]) <= near]
    check(len(sl) > 10 and abs(max(sl) - float(last[f"max_slip_near_{s}_m"])) <= 1e-12 * max(1, max(sl)),
          f"set {s}: largest slip near the opening {max(sl) * 1e3:.4f} mm, as in events.csv")
k = np.zeros(3)
for c in ct:
    if float(c["distance_to_wall_m"]) > near:
        continue
    a, L = float(c["aperture_m"]), float(c["length_m"])
    if c["state"] == "open":
        L *= 0.5
    n = np.array([float(c["normal_x"]), float(c["normal_y"])])
    w = a ** 3 / 12 * L / area
    k += w * np.array([1 - n[0] ** 2, 1 - n[1] ** 2, -n[0] * n[1]])
got = np.array([float(last[c]) for c in ("k_xx_m2", "k_yy_m2", "k_xy_m2")])
check(np.allclose(k, got, rtol=1e-6, atol=0), f"permeability {got} from the apertures ({k})")
check(all(float(c["aperture_m"]) >= 3e-5 for c in ct), "no aperture below the residual")
done()
PY
# The same results as VTK fields (ParaView): one joints_/blocks_ file per stage from the reference
# on, collections listing them at the stages' times, the joint fields equal to contacts_*.csv.
PYTHONPATH="$src/tests/cli/lib" /usr/bin/python3 - "$tmp/a" <<'PY' || fail=1
import sys, csv, re
import numpy as np
import vtk
from vtk.util.numpy_support import vtk_to_numpy
out = sys.argv[1] + "/drift"
from checks import check, done
def read(path):
    r = vtk.vtkXMLUnstructuredGridReader()
    r.SetFileName(path)
    r.Update()
    return r.GetOutput()
ev = [r for r in csv.DictReader(l for l in open(out + "/events.csv") if not l.startswith("#"))]
tags = [f"{r['stage']}_{r['name']}" for r in ev]
for kind in ("joints", "blocks"):
    pvd = open(f"{out}/{kind}.pvd").read()
    files = re.findall(r'file="([^"]+)"', pvd)
    times = [float(t) for t in re.findall(r'timestep="([^"]+)"', pvd)]
    check(files == [f"{kind}_{t}.vtu" for t in tags] and np.allclose(times, [float(r["time_s"]) for r in ev]),
          f"{kind}.pvd lists {len(files)} stages at their end times")
g = read(f"{out}/joints_{tags[-1]}.vtu")
ct = [r for r in csv.DictReader(l for l in open(f"{out}/contacts_{tags[-1]}.csv") if not l.startswith("#"))]
pd = g.GetPointData()
same = g.GetNumberOfPoints() == len(ct)
for field, col in (("slip_m", "slip_m"), ("opening_m", "opening_m"), ("aperture_m", "aperture_m"),
                   ("distance_to_wall_m", "distance_to_wall_m"), ("normal_stress_Pa", "normal_stress_Pa")):
    a = vtk_to_numpy(pd.GetArray(field))
    same = same and np.allclose(a, [float(c[col]) for c in ct], rtol=1e-8, atol=1e-15)
names = [g.GetFieldData().GetAbstractArray("joint_set_names").GetValue(i) for i in range(g.GetFieldData().GetAbstractArray("joint_set_names").GetNumberOfValues())]
sets = vtk_to_numpy(pd.GetArray("joint_set"))
same = same and [names[i] for i in sets] == [c["set"] for c in ct]
check(same, f"joints_{tags[-1]}.vtu: {g.GetNumberOfPoints()} joint contacts, slip, opening, aperture, set as in the CSV")
b = read(f"{out}/blocks_{tags[-1]}.vtu")
moved = vtk_to_numpy(b.GetCellData().GetArray("moved_m"))
fallen = vtk_to_numpy(b.GetCellData().GetArray("fallen"))
check(b.GetNumberOfCells() > 10 and np.nanmax(moved) < 0.01 and fallen.sum() == 0,
      f"blocks_{tags[-1]}.vtu: {b.GetNumberOfCells()} blocks, largest move {np.nanmax(moved) * 1e3:.3f} mm, none fallen")
done()
PY

n=$(grep -vc '^#' "$tmp/a/drift/fallen_blocks.csv")
[ "$n" = 1 ] && ok "no block fell at 2 cm" || bad "blocks listed as fallen at 2 cm: $((n - 1))"

# A low threshold lists the blocks that moved towards the opening.
sed 's/^fall_displacement = .*/fall_displacement = "0.1 mm"/' "$case_file" > "$tmp/low.toml"
"$bin" run "$tmp/low.toml" --out "$tmp/low" --quiet || bad "low-threshold run exited $?"
/usr/bin/python3 - "$tmp/low" <<'PY' || fail=1
import sys, csv
out = sys.argv[1]
fb = list(csv.DictReader(l for l in open(out + "/drift/fallen_blocks.csv") if not l.startswith("#")))
ev = list(csv.DictReader(l for l in open(out + "/drift/events.csv") if not l.startswith("#")))
# Listed: the blocks beyond the threshold at the last stage's end (as events.csv counts them
# there), each with the stage since which it has been beyond it at every stage end; a block out
# after the first stage and back within the threshold after the second (the rock rebounds) is
# counted in the first stage's row of events.csv only.
thr = 1e-4
out_first = int(float(ev[1]["fallen_blocks"]))
since_first = sum(b["stage_name"] == "loosen" for b in fb)
good = len(fb) > 0 and all(float(b["displacement_m"]) > thr and b["stage_name"] in ("loosen", "settle") for b in fb)
good = good and since_first <= out_first and int(float(ev[2]["fallen_blocks"])) == len(fb) and ev[0]["fallen_blocks"] == "0"
print(("ok   " if good else "FAIL ") + f"0.1 mm: {len(fb)} blocks listed, each beyond it now (first: {', '.join(b['name'] for b in fb[:5])}); "
      f"{out_first} beyond it after the first stage, {since_first} of them still beyond it after the second, as events.csv counts")
sys.exit(0 if good else 1)
PY

# Restart from the middle stage: the same results.
cp -r "$tmp/a" "$tmp/r"
"$bin" run "$case_file" --out "$tmp/r" --restart "$tmp/r/stage_3_loosen.h5" --quiet > /dev/null || bad "restart exited $?"
for f in events.csv fallen_blocks.csv contacts_4_settle.csv joints_4_settle.vtu blocks_4_settle.vtu joints.pvd blocks.pvd; do
  cmp -s "$tmp/a/drift/$f" "$tmp/r/drift/$f" && ok "restart from stage 3: $f identical" || bad "restart from stage 3: $f differs"
done

# Two processes: the same results.
mpirun -np 2 "$bin" run "$case_file" --out "$tmp/p2" --quiet > "$tmp/p2.log" 2>&1 || { cat "$tmp/p2.log"; bad "2-process run exited"; }
for f in events.csv fallen_blocks.csv contacts_3_loosen.csv contacts_4_settle.csv joints_4_settle.vtu blocks_4_settle.vtu; do
  cmp -s "$tmp/a/drift/$f" "$tmp/p2/drift/$f" && ok "2 processes: $f identical" || bad "2 processes: $f differs"
done

# Bad input: each refused with exit 2, naming the key.
expect_bad() {  # name, sed expression, text expected in the message
  sed "$2" "$case_file" > "$tmp/bad.toml"
  msg=$("$bin" run "$tmp/bad.toml" --out "$tmp/bad_$1" --quiet 2>&1)
  rc=$?
  if [ $rc = 2 ] && grep -q -- "$3" <<< "$msg"; then ok "bad input ($1): exit 2, '$3'"; else bad "bad input ($1): exit $rc: $msg"; fi
}
expect_bad opening 's/^opening = "opening"/opening = "tunnel"/' "drift.opening"
expect_bad not_excavated 's/^excavate = \["opening"\]/excavate = ["rm.3"]/' "no stage excavates 'opening'"
expect_bad stage 's/^near = "1.6 m"/near = "1.6 m"\nreference_stage = "settel"/' "no stage named 'settel'"
expect_bad early 's/^near = "1.6 m"/near = "1.6 m"\nreference_stage = "in_situ"/' "before the opening is excavated"
expect_bad near 's/^near = "1.6 m"/near = "-1 m"/' "'near' must be a positive length"
expect_bad residual 's/^near = "1.6 m"/near = "1.6 m"\nresidual_aperture = "1 mm"/' "at most initial_aperture"
expect_bad key 's/^near = "1.6 m"/nearby = "1.6 m"/' "did you mean 'near'"
exit $fail
