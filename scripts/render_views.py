"""The standard views of a `rockdem run` folder as PNG files, without ParaView or a display.

Usage: /usr/bin/python3 scripts/render_views.py RUN_DIR [--step N | --time T] [--out DIR]
                                                 [--stress-component S] [--relative-to BLOCK]

Reads RUN_DIR/vtk/blocks.pvd and contacts.pvd (the VTK fields `rockdem run` writes; docs/
user-guide-output.md), picks one output step (default the last; --step N exactly, or --time T
the nearest output time in simulated seconds) and writes into DIR (default RUN_DIR/views/):

  blocks_displacement.png    blocks at their present place, coloured by the size of the
                             displacement since the start [mm] (or relative to the rigid motion
                             of a block or group, --relative-to: a seismic input moves the whole
                             model), outlines drawn;
  blocks_stress.png          the zones' and rigid blocks' stress [MPa], compression positive:
                             the major principal stress (default) or xx, yy, xy;
  contacts_state.png         contact points by state (elastic, slipping, open; the names stored
                             in the file), over the block outlines;
  contacts_normal_stress.png contact points coloured by joint normal stress [MPa].

It prints what it drew (counts per contact state, the ranges shown). Exit 0 when the views are
written, 2 for bad input (a folder that is no run folder, a run without VTK output, a step that
was not written), 1 when a file cannot be read or written.

Why not pvpython: Debian 12's python3-paraview conflicts with libvtk9-dev, which rockdem builds
with, and VTK's own off-screen rendering needs an X server on Debian's build. This script uses
VTK's readers (python3-vtk9, installed with libvtk9-dev) and matplotlib (python3-matplotlib), so
it runs headless wherever rockdem builds. ParaView remains the tool for looking around; these are
the views a report or a quick look needs.
"""
import argparse
import difflib
import json
import os
import sys
import xml.etree.ElementTree as ET

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from matplotlib.collections import LineCollection, PolyCollection  # noqa: E402
from matplotlib.lines import Line2D  # noqa: E402

try:
    import vtk  # noqa: E402
    from vtk.util.numpy_support import vtk_to_numpy  # noqa: E402
except ImportError:  # pragma: no cover - depends on the machine
    sys.stderr.write("render_views.py: VTK's Python module is missing: install python3-vtk9 "
                     "(it comes with libvtk9-dev) and run with /usr/bin/python3\n")
    sys.exit(1)


class BadInput(Exception):
    pass


# Colours for the contact states, by name (the file stores the names; unknown names get grey).
STATE_COLOURS = {"elastic": "#1f77b4", "slipping": "#d62728", "open": "#a0a0a0"}


def read_pvd(path):
    """(time, file) entries of a ParaView collection, in file order."""
    try:
        root = ET.parse(path).getroot()
    except (OSError, ET.ParseError) as e:
        raise BadInput(f"cannot read the ParaView collection '{path}': {e}")
    out = []
    for ds in root.iter("DataSet"):
        if ds.get("timestep") is None or ds.get("file") is None:
            continue
        try:
            out.append((float(ds.get("timestep")), ds.get("file")))
        except ValueError:
            raise BadInput(f"'{path}': timestep '{ds.get('timestep')}' is not a number")
    if not out:
        raise BadInput(f"'{path}' lists no output steps")
    return out


def step_of(file_name):
    """The step number in a name like blocks_000001200.pvtu."""
    stem = os.path.splitext(os.path.basename(file_name))[0]
    try:
        return int(stem.rsplit("_", 1)[1])
    except (IndexError, ValueError):
        return None


def pick(entries, step, time, what):
    if step is not None:
        for t, f in entries:
            if step_of(f) == step:
                return t, f
        steps = [step_of(f) for _, f in entries]
        raise BadInput(f"--step {step}: {what} has no output at that step; written steps: "
                       f"{steps[0]} .. {steps[-1]} ({len(steps)} outputs), e.g. {', '.join(map(str, steps[-3:]))}")
    if time is not None:
        return min(entries, key=lambda e: abs(e[0] - time))
    return entries[-1]


def read_vtu(path):
    if not os.path.isfile(path):
        raise BadInput(f"'{path}' is listed in its collection but does not exist")
    # A step's .pvtu (its pieces, one per process of the run) or a single piece
    r = vtk.vtkXMLPUnstructuredGridReader() if path.endswith(".pvtu") else vtk.vtkXMLUnstructuredGridReader()
    r.SetFileName(path)
    r.Update()
    g = r.GetOutput()
    if g is None or g.GetNumberOfPoints() == 0 and g.GetNumberOfCells() == 0 and os.path.getsize(path) == 0:
        raise BadInput(f"cannot read '{path}'")
    return g


def array(data, name, path):
    a = data.GetArray(name)
    if a is None:
        raise BadInput(f"'{path}' has no array '{name}' (written by an older rockdem? re-run the case)")
    return vtk_to_numpy(a)


def names(grid, name):
    a = grid.GetFieldData().GetAbstractArray(name)
    if a is None:
        return []
    return [a.GetValue(i) for i in range(a.GetNumberOfValues())]


def cells_of(grid):
    """Each cell's point ids, as a list of arrays (triangles and polygons)."""
    out = []
    ids = vtk.vtkIdList()
    for c in range(grid.GetNumberOfCells()):
        grid.GetCellPoints(c, ids)
        out.append(np.array([ids.GetId(k) for k in range(ids.GetNumberOfIds())], dtype=np.int64))
    return out


def outline_segments(cells, block, xy):
    """Edges on a block's boundary: the edges of its cells that no other cell of it shares."""
    count = {}
    for c, pts in enumerate(cells):
        b = int(block[c])
        for k in range(len(pts)):
            a, e = int(pts[k]), int(pts[(k + 1) % len(pts)])
            key = (b, min(a, e), max(a, e))
            count[key] = count.get(key, 0) + 1
    edges = [(a, e) for (b, a, e), n in count.items() if n == 1]
    return [(xy[a], xy[e]) for a, e in edges]


def frame(ax, xy, title):
    pad = 0.03 * max(np.ptp(xy[:, 0]), np.ptp(xy[:, 1]), 1e-9)
    ax.set_xlim(xy[:, 0].min() - pad, xy[:, 0].max() + pad)
    ax.set_ylim(xy[:, 1].min() - pad, xy[:, 1].max() + pad)
    ax.set_aspect("equal")
    ax.set_xlabel("x [m]")
    ax.set_ylabel("y [m]")
    ax.set_title(title, fontsize=10)


def principal_major_compression(s):
    """Major principal stress, compression positive [Pa], from rows (xx, yy, zz, xy, yz, xz)
    in the tension-positive convention: minus the smallest in-plane eigenvalue."""
    xx, yy, xy = s[:, 0], s[:, 1], s[:, 3]
    centre, radius = 0.5 * (xx + yy), np.sqrt((0.5 * (xx - yy)) ** 2 + xy ** 2)
    return -(centre - radius)


def colour_range(values):
    """Colour limits that a few extreme cells (a stress concentration at a sharp corner) do not
    take over: the 1st and 99th percentiles when the extremes lie well beyond them, with arrows
    on the colour bar saying so; else the full range."""
    if values.size == 0:
        return 0.0, 1.0, "neither"
    full_lo, full_hi = float(values.min()), float(values.max())
    lo, hi = (float(v) for v in np.percentile(values, [1, 99]))
    span = max(hi - lo, 1e-300)
    clip_lo, clip_hi = full_lo < lo - 0.25 * span, full_hi > hi + 0.25 * span
    lo, hi = (lo if clip_lo else full_lo), (hi if clip_hi else full_hi)
    if hi <= lo:
        hi = lo + max(abs(lo), 1.0) * 1e-9
    extend = {(False, False): "neither", (True, False): "min", (False, True): "max", (True, True): "both"}
    return lo, hi, extend[(clip_lo, clip_hi)]


def relative_displacement(x, d, ref):
    """Displacements d of points now at x, less the rigid motion (rotation and translation) that
    best maps the reference points `ref` from where they started (x - d) onto where they are, by
    least squares (2D Kabsch), as the drift study measures from the far field's frame."""
    x0 = x - d
    c0, c1 = x0[ref].mean(axis=0), x[ref].mean(axis=0)
    a, b = x0[ref] - c0, x[ref] - c1
    h = a.T @ b
    theta = np.arctan2(h[0, 1] - h[1, 0], h[0, 0] + h[1, 1])
    r = np.array([[np.cos(theta), -np.sin(theta)], [np.sin(theta), np.cos(theta)]])
    return x - ((x0 - c0) @ r.T + c1)


def span(values, unit):
    """'lo .. hi unit' of the finite values shown, or a word when there are none."""
    if values.size == 0:
        return "no values"
    return f"{values.min() + 0.0:.4g} .. {values.max() + 0.0:.4g} {unit}"


def save(fig, path):
    try:
        tmp = path + ".tmp.png"
        fig.savefig(tmp, dpi=130, bbox_inches="tight")
        os.replace(tmp, path)
    except OSError as e:
        plt.close(fig)
        raise OSError(f"cannot write '{path}': {e}")
    plt.close(fig)


def main(argv):
    p = argparse.ArgumentParser(description="Render the standard views of a rockdem run folder to PNG.")
    p.add_argument("run_dir")
    g = p.add_mutually_exclusive_group()
    g.add_argument("--step", type=int, help="the output step to draw (as in the .pvtu names)")
    g.add_argument("--time", type=float, help="draw the output nearest this simulated time [s]")
    p.add_argument("--out", help="folder for the PNGs (default RUN_DIR/views)")
    p.add_argument("--stress-component", default="major", choices=["major", "xx", "yy", "xy"],
                   help="what blocks_stress.png shows (default: the major principal stress)")
    p.add_argument("--relative-to", metavar="BLOCK",
                   help="show displacements relative to this block's or block group's rigid motion "
                        "(e.g. the far field in a seismic run, whose input moves the whole model)")
    a = p.parse_args(argv)

    run, vdir = a.run_dir, os.path.join(a.run_dir, "vtk")
    if not os.path.isdir(run):
        raise BadInput(f"'{run}' is not a folder (give the folder `rockdem run --out` wrote)")
    blocks_pvd = os.path.join(vdir, "blocks.pvd")
    if not os.path.isfile(blocks_pvd):
        raise BadInput(f"'{run}' has no vtk/blocks.pvd: not a `rockdem run` folder, or the case has "
                       f"[output] vtk_interval = 0 (no VTK output)")
    case = os.path.basename(os.path.normpath(run))
    try:
        with open(os.path.join(run, "manifest.json")) as f:
            case = os.path.splitext(os.path.basename(json.load(f).get("case_file", "")))[0] or case
    except (OSError, ValueError):
        pass

    t, bfile = pick(read_pvd(blocks_pvd), a.step, a.time, "vtk/blocks.pvd")
    step = step_of(bfile)
    bpath = os.path.join(vdir, bfile)
    grid = read_vtu(bpath)
    xy = vtk_to_numpy(grid.GetPoints().GetData())[:, :2]
    cells = cells_of(grid)
    cd, pd = grid.GetCellData(), grid.GetPointData()
    block = array(cd, "block_id", bpath)
    disp = array(pd, "displacement_m", bpath)
    stress = array(cd, "stress_Pa", bpath)
    outline = outline_segments(cells, block, xy)
    polys = [xy[c] for c in cells]
    when = f"{case}: step {step}, t = {t:.6g} s"
    print(f"drawing {when}")

    out = a.out or os.path.join(run, "views")
    try:
        os.makedirs(out, exist_ok=True)
    except OSError as e:
        raise OSError(f"cannot create '{out}': {e}")

    def blocks_view(values, label, file_name, cmap):
        fig, ax = plt.subplots(figsize=(7.5, 6.5))
        finite = values[np.isfinite(values)]
        cmap = matplotlib.colormaps[cmap].copy()
        cmap.set_bad("0.85")  # cells without a value (held rigid blocks' stress): light grey
        pc = PolyCollection(polys, array=np.ma.masked_invalid(values), cmap=cmap, edgecolors="face", linewidths=0.2)
        lo, hi, extend = colour_range(finite)
        pc.set_clim(lo, hi)
        ax.add_collection(pc)
        ax.add_collection(LineCollection(outline, colors="k", linewidths=0.4))
        fig.colorbar(pc, ax=ax, label=label, shrink=0.85, extend=extend)
        missing = int(np.count_nonzero(~np.isfinite(values)))
        note = f"\n(grey: {missing} cells without a value)" if missing else ""
        frame(ax, xy, f"{label}\n{when}{note}")
        save(fig, os.path.join(out, file_name))
        return finite

    # Displacement per cell: the mean of its points' displacement magnitudes; with --relative-to,
    # less the named block's or group's rigid motion (a seismic input moves the whole model).
    d2 = disp[:, :2].copy()
    dlabel = "displacement since the start [mm]"
    if a.relative_to:
        bname = grid.GetCellData().GetAbstractArray("block_name")
        if bname is None:
            raise BadInput(f"'{bpath}' has no block_name array (written by an older rockdem? re-run the case)")
        cell_names = [bname.GetValue(i) for i in range(bname.GetNumberOfValues())]
        mine = sorted({int(k) for c, n in zip(cells, cell_names) if n == a.relative_to for k in c})
        groups = names(grid, "group_names")
        if not mine and a.relative_to in groups:  # a group of blocks (e.g. a rock mass's far field)
            gi = groups.index(a.relative_to)
            gcell = array(cd, "group", bpath)
            mine = sorted({int(k) for c, gg in zip(cells, gcell) if int(gg) == gi for k in c})
        if not mine:
            known = sorted(set(cell_names)) + sorted(set(groups) - set(cell_names))
            near = difflib.get_close_matches(a.relative_to, known, n=1)
            raise BadInput(f"--relative-to: no block or group '{a.relative_to}' in {bfile}"
                           + (f" (did you mean '{near[0]}'?)" if near else "")
                           + f"; groups: {', '.join(groups)}; blocks: {', '.join(sorted(set(cell_names))[:12])}"
                           + (", ..." if len(set(cell_names)) > 12 else ""))
        d2 = relative_displacement(xy, d2, mine)
        dlabel = f"displacement relative to {a.relative_to} [mm]"
    dmag = np.linalg.norm(d2, axis=1) * 1e3
    cell_disp = np.array([dmag[c].mean() for c in cells])
    shown = blocks_view(cell_disp, dlabel, "blocks_displacement.png", "viridis")
    print(f"blocks_displacement.png: {len(set(block.tolist()))} blocks, {len(cells)} cells, {dlabel.split(' [')[0]} "
          f"{span(shown, 'mm')}" + ("" if a.relative_to else " (the whole model's motion included)"))

    comp = a.stress_component
    if comp == "major":
        sv, slabel = principal_major_compression(stress), "major principal stress, compression positive [MPa]"
    else:
        k = {"xx": 0, "yy": 1, "xy": 3}[comp]
        # Tension-positive in the file; shown compression positive as rock engineers read it.
        sv, slabel = -stress[:, k], f"stress {comp.upper()}, compression positive [MPa]"
    shown = blocks_view(sv / 1e6, slabel, "blocks_stress.png", "plasma")
    held = int(np.count_nonzero(~np.isfinite(sv)))
    print(f"blocks_stress.png: {slabel}: {span(shown, 'MPa')}"
          + (f"; {held} cells of held rigid blocks without a known stress (grey)" if held else ""))

    contacts_pvd = os.path.join(vdir, "contacts.pvd")
    if not os.path.isfile(contacts_pvd):
        print("no vtk/contacts.pvd: contact views skipped (the run wrote no contact fields)")
        print(f"views in {out}")
        return 0
    entries = read_pvd(contacts_pvd)
    match = [e for e in entries if step_of(e[1]) == step]
    if not match:
        raise BadInput(f"vtk/contacts.pvd has no output at step {step} (vtk/blocks.pvd has)")
    cpath = os.path.join(vdir, match[0][1])
    cgrid = read_vtu(cpath)
    n = cgrid.GetNumberOfPoints()
    cxy = vtk_to_numpy(cgrid.GetPoints().GetData())[:, :2] if n else np.zeros((0, 2))
    cpd = cgrid.GetPointData()
    state = array(cpd, "state", cpath) if n else np.zeros(0, dtype=int)
    sn = array(cpd, "normal_stress_Pa", cpath) if n else np.zeros(0)
    state_names = names(cgrid, "state_names") or ["elastic", "slipping", "open"]
    size = max(3.0, min(16.0, 12000.0 / max(n, 1)))

    fig, ax = plt.subplots(figsize=(7.5, 6.5))
    ax.add_collection(LineCollection(outline, colors="0.6", linewidths=0.4))
    handles, counts = [], []
    for k, name in enumerate(state_names):
        sel = state == k
        counts.append(f"{int(sel.sum())} {name}")
        colour = STATE_COLOURS.get(name, "0.5")
        if sel.any():
            ax.scatter(cxy[sel, 0], cxy[sel, 1], s=size, c=colour, linewidths=0, zorder=3)
        handles.append(Line2D([], [], marker="o", ls="", color=colour, label=f"{name} ({int(sel.sum())})"))
    ax.legend(handles=handles, loc="upper right", fontsize=8, title="contact state", title_fontsize=8)
    frame(ax, xy, f"contact points by state\n{when}")
    save(fig, os.path.join(out, "contacts_state.png"))
    print(f"contacts_state.png: {n} contact points: {', '.join(counts)}")

    fig, ax = plt.subplots(figsize=(7.5, 6.5))
    ax.add_collection(LineCollection(outline, colors="0.6", linewidths=0.4))
    lo, hi, extend = colour_range(sn[np.isfinite(sn)] / 1e6)
    sc = ax.scatter(cxy[:, 0], cxy[:, 1], s=size, c=sn / 1e6, cmap="plasma", vmin=lo, vmax=hi, linewidths=0, zorder=3)
    fig.colorbar(sc, ax=ax, label="joint normal stress, compression positive [MPa]", shrink=0.85, extend=extend)
    frame(ax, xy, f"joint normal stress at the contact points\n{when}")
    save(fig, os.path.join(out, "contacts_normal_stress.png"))
    print(f"contacts_normal_stress.png: {span(sn[np.isfinite(sn)] / 1e6, 'MPa')}")
    print(f"views in {out}")
    return 0


if __name__ == "__main__":
    try:
        sys.exit(main(sys.argv[1:]))
    except BadInput as e:
        sys.stderr.write(f"render_views.py: {e}\n")
        sys.exit(2)
    except OSError as e:
        sys.stderr.write(f"render_views.py: {e}\n")
        sys.exit(1)
