#!/usr/bin/python3
"""Section pictures of the specimen from its VTK snapshots (headless, PNG).

    scripts/specimen_section.py DIR [--out PNG] [--all] [--plane y] [--quiet]

DIR holds a snapshot series (io/vtk_snapshot_writer.h: snapshots.csv,
particles_k.vtp, contacts_k.vtp), written by `triax_run --specimen DIR`, by
dem_node (~snapshot_dir; the main job's OUT/specimen) or by `triax_snapshot`.
Writes DIR/specimen_section.png (or --out): the first and the last snapshot
side by side (before and after the test, e.g. before and after shearing),
each a section through the middle of the periodic cell normal to --plane
(default y: x to the right, z up; z is the axial axis of the shipped
protocols):
  - particles cut by the plane, drawn as their cut: circles for spheres,
    ellipses for spheroids (the exact plane section of the ellipsoid);
    grey = carries load, orange = idle (fewer than 3 contacts after the
    iterative removal of section 4.5), periodic images included;
  - force chains: contacts whose contact point lies within one mean radius
    of the plane, as lines between the centres projected on the plane, line
    width proportional to the normal force (the same scale in both panels),
    red = sliding (at the Coulomb cap), black = sticking.
--all also writes DIR/section_k.png for every snapshot. The reader parses
the ASCII VTK XML itself (numpy only), so the script needs no VTK; the
read-back tests use Debian's python3-vtk9 as an independent reader.
Importable: render(dir, out_png) for reports. Exit status 2 on bad input.
"""
import argparse
import csv
import os
import sys
import xml.etree.ElementTree as ET

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from matplotlib.collections import EllipseCollection, LineCollection  # noqa: E402
from matplotlib.patches import Rectangle  # noqa: E402

AXES = {"x": 0, "y": 1, "z": 2}
MAX_WIDTH_PT = 3.0  # line width of the largest normal force


def read_vtp(path):
    """{name: array} of the point, cell and field data and the points of one .vtp."""
    root = ET.parse(path).getroot()
    out = {}
    for section in ("FieldData", "PointData", "CellData", "Points"):
        for node in root.iter(section):
            for arr in node.findall("DataArray"):
                comps = int(arr.get("NumberOfComponents", "1"))
                vals = np.array((arr.text or "").split(), dtype=float)
                if comps > 1 and section != "FieldData":
                    vals = vals.reshape(-1, comps)
                key = arr.get("Name") if section != "Points" else "Points"
                out[(section, key)] = vals
    return out


def read_series(directory):
    path = os.path.join(directory, "snapshots.csv")
    if not os.path.isfile(path):
        raise ValueError(f"{path}: missing (not a snapshot directory)")
    with open(path, newline="") as f:
        rows = list(csv.DictReader(f))
    if not rows:
        raise ValueError(f"{path}: no snapshot")
    return rows


def load_snapshot(directory, index):
    p = read_vtp(os.path.join(directory, f"particles_{index:06d}.vtp"))
    c = read_vtp(os.path.join(directory, f"contacts_{index:06d}.vtp"))
    return p, c


def section_of_particles(p, plane, h):
    """Cuts of the particles by the mid plane: list of (centre 2D, width, height, angle deg, idle)."""
    n_ax = AXES[plane]
    u_ax, v_ax = [a for a in range(3) if a != n_ax]
    lengths = np.diag(h)
    x = p[("Points", "Points")]
    sem = p[("PointData", "semi_axes")].reshape(-1, 3)
    axis = p[("PointData", "symmetry_axis")].reshape(-1, 3)
    idle = p[("PointData", "idle")].astype(bool)
    y0 = 0.5 * lengths[n_ax]
    dy = x[:, n_ax] - y0
    dy -= lengths[n_ax] * np.round(dy / lengths[n_ax])
    a, b = sem[:, 0], sem[:, 1]
    cut = np.abs(dy) < a
    cu, cv, w, hgt, ang, idl = [], [], [], [], [], []
    for i in np.nonzero(cut)[0]:
        e = axis[i]
        # Ellipsoid (q - c)^T A (q - c) = 1, A = I/b^2 + (1/a^2 - 1/b^2) e e^T.
        A = np.eye(3) / b[i] ** 2 + (1.0 / a[i] ** 2 - 1.0 / b[i] ** 2) * np.outer(e, e)
        M = A[np.ix_([u_ax, v_ax], [u_ax, v_ax])]
        g = dy[i] * A[[u_ax, v_ax], n_ax]
        Minv_g = np.linalg.solve(M, g)
        k = 1.0 - A[n_ax, n_ax] * dy[i] ** 2 + g @ Minv_g
        if k <= 0:
            continue
        lam, vec = np.linalg.eigh(M / k)
        semi = 1.0 / np.sqrt(lam)
        cu.append(x[i, u_ax] - Minv_g[0])
        cv.append(x[i, v_ax] - Minv_g[1])
        w.append(2 * semi[0])
        hgt.append(2 * semi[1])
        ang.append(np.degrees(np.arctan2(vec[1, 0], vec[0, 0])))
        idl.append(idle[i])
    return (np.array(cu), np.array(cv), np.array(w), np.array(hgt), np.array(ang), np.array(idl, dtype=bool),
            (u_ax, v_ax, lengths))


def chains_near_plane(p, c, plane, h):
    """Force-chain segments (2D) near the mid plane with their normal force and sliding flag."""
    n_ax = AXES[plane]
    u_ax, v_ax = [a for a in range(3) if a != n_ax]
    lengths = np.diag(h)
    if ("Points", "Points") not in c or c[("Points", "Points")].size == 0:
        return np.zeros((0, 2, 2)), np.zeros(0), np.zeros(0, dtype=bool)
    pts = c[("Points", "Points")].reshape(-1, 2, 3)
    fn = c[("CellData", "normal_force")]
    sliding = c[("CellData", "sliding")].astype(bool)
    r_mean = float(np.mean(p[("PointData", "radius")]))
    mid = 0.5 * (pts[:, 0, n_ax] + pts[:, 1, n_ax]) - 0.5 * lengths[n_ax]
    mid -= lengths[n_ax] * np.round(mid / lengths[n_ax])
    near = np.abs(mid) < r_mean
    seg = pts[near][:, :, [u_ax, v_ax]]
    return seg, fn[near], sliding[near]


def periodic_images(lengths_2d):
    lu, lv = lengths_2d
    return [(su * lu, sv * lv) for su in (-1, 0, 1) for sv in (-1, 0, 1)]


def draw(ax, p, c, plane, fmax, title, limits):
    h = p[("FieldData", "cell_matrix")].reshape(3, 3)
    cu, cv, w, hgt, ang, idl, (u_ax, v_ax, lengths) = section_of_particles(p, plane, h)
    lu, lv = lengths[u_ax], lengths[v_ax]
    seg, fn, sliding = chains_near_plane(p, c, plane, h)
    cell = Rectangle((0, 0), lu, lv, transform=ax.transData)  # draw inside the cell only
    for du, dv in periodic_images((lu, lv)):
        for mask, color in ((~idl, "0.78"), (idl, "#f4a259")):
            if np.any(mask):
                ax.add_collection(EllipseCollection(w[mask], hgt[mask], ang[mask], units="xy",
                                                    offsets=np.column_stack([cu[mask] + du, cv[mask] + dv]),
                                                    offset_transform=ax.transData, facecolors=color,
                                                    edgecolors="0.45", linewidths=0.3)).set_clip_path(cell)
        if len(seg):
            shifted = seg + np.array([du, dv])
            widths = MAX_WIDTH_PT * fn / fmax if fmax > 0 else np.zeros_like(fn)
            colors = np.where(sliding[:, None], [[0.85, 0.1, 0.1, 1.0]], [[0.0, 0.0, 0.0, 1.0]])
            ax.add_collection(LineCollection(shifted, linewidths=widths, colors=colors,
                                             capstyle="round")).set_clip_path(cell)
    ax.plot([0, lu, lu, 0, 0], [0, 0, lv, lv, 0], color="tab:blue", lw=1.0)  # the periodic cell
    ax.set_xlim(0, limits[0])
    ax.set_ylim(0, limits[1])
    ax.set_aspect("equal")
    names = "xyz"
    ax.set_xlabel(f"{names[u_ax]} [mm]")
    ax.set_ylabel(f"{names[v_ax]} [mm]")
    ax.xaxis.set_major_formatter(matplotlib.ticker.FuncFormatter(lambda v, _: f"{v * 1e3:g}"))
    ax.yaxis.set_major_formatter(matplotlib.ticker.FuncFormatter(lambda v, _: f"{v * 1e3:g}"))
    ax.set_title(title, fontsize=9)
    return len(cu), len(seg)


def describe(row, p):
    s = p[("FieldData", "stress")].reshape(3, 3)
    pm = np.trace(s) / 3.0
    q = s[2, 2] - min(s[0, 0], s[1, 1])
    eps = p[("FieldData", "strain")]
    return (f"{row['label']}\nstep {row['step']}, eps_z {100 * eps[2]:.2f} %, p {pm / 1e3:.1f} kPa, "
            f"q {q / 1e3:.1f} kPa")


def render(directory, out_png, plane="y", indices=None):
    """The first and the last snapshot (or `indices`) side by side in one PNG."""
    rows = read_series(directory)
    if indices is None:
        indices = [0, len(rows) - 1] if len(rows) > 1 else [0]
    snaps = [load_snapshot(directory, int(rows[k]["index"])) for k in indices]
    fmax = max((float(np.max(c[("CellData", "normal_force")])) if ("CellData", "normal_force") in c and
                c[("CellData", "normal_force")].size else 0.0) for _, c in snaps)
    # one length scale for all panels: the largest cell extent of the section plane's axes
    n_ax = AXES[plane]
    u_ax, v_ax = [a for a in range(3) if a != n_ax]
    diag = [np.diag(p[("FieldData", "cell_matrix")].reshape(3, 3)) for p, _ in snaps]
    limits = (max(d[u_ax] for d in diag), max(d[v_ax] for d in diag))
    fig, axes = plt.subplots(1, len(snaps), figsize=(5.2 * len(snaps), 5.6), squeeze=False)
    for ax, k, (p, c) in zip(axes[0], indices, snaps):
        draw(ax, p, c, plane, fmax, describe(rows[k], p), limits)
    fig.suptitle(f"section through the cell centre normal to {plane}: particles cut by the plane "
                 f"(orange: idle), force chains within one mean radius\n(line width proportional to the normal "
                 f"force, widest = {fmax:.3g} N; red: sliding)", fontsize=9)
    fig.tight_layout()
    fig.savefig(out_png, dpi=130, bbox_inches="tight")
    plt.close(fig)
    return out_png


def main(argv):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("dir")
    ap.add_argument("--out", help="PNG path (default DIR/specimen_section.png)")
    ap.add_argument("--all", action="store_true", help="also DIR/section_k.png for every snapshot")
    ap.add_argument("--plane", choices=["x", "y", "z"], default="y", help="normal of the section plane")
    ap.add_argument("--quiet", action="store_true")
    a = ap.parse_args(argv)
    try:
        out = render(a.dir, a.out or os.path.join(a.dir, "specimen_section.png"), a.plane)
        written = [out]
        if a.all:
            for k in range(len(read_series(a.dir))):
                written.append(render(a.dir, os.path.join(a.dir, f"section_{k:06d}.png"), a.plane, [k]))
    except (OSError, ValueError, KeyError, ET.ParseError) as e:
        print(f"specimen_section: error: {e}", file=sys.stderr)
        return 2
    if not a.quiet:
        for w in written:
            print(f"specimen_section: wrote {w}", file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
