"""Shared drawing helpers for the PhysIK testbed's figures (matplotlib, no physics here).

Tables come from the C++ side (see physik/pose_io.h):
  bones table       one row per bone: bone, parent, head_x..z, tail_x..z (world, rig units)
  trajectory table  one row per step; bone columns "<bone>.head_x" ... "<bone>.tail_z"
Experiment tables: each experiment records its tables' schemas in its summary.json ("tables": file,
rows, columns with name, unit, doc, format); read_table checks a CSV against its schema.
Views follow the paper's Blender screenshots: front looks along +Y (x right, z up), side looks
along -X (y right, z up).
"""
import csv
import json
import os

import matplotlib

matplotlib.use(os.environ.get("MPLBACKEND", "Agg"))
import matplotlib.pyplot as plt  # noqa: E402

VIEWS = {"front": (0, 2, "x", "z"), "side": (1, 2, "y", "z")}


def read_bones_csv(path):
    """Return a list of dicts {bone, parent, head: (x,y,z), tail: (x,y,z)}."""
    bones = []
    with open(path, newline="") as f:
        for row in csv.DictReader(f):
            bones.append({
                "bone": row["bone"],
                "parent": row["parent"],
                "head": tuple(float(row["head_" + a]) for a in "xyz"),
                "tail": tuple(float(row["tail_" + a]) for a in "xyz"),
            })
    if not bones:
        raise ValueError("%s: no bones" % path)
    return bones


class TableColumns(dict):
    """{column: [values]} read from one CSV; a column it lacks is a KeyError naming the file."""

    def __init__(self, path, columns):
        super().__init__(columns)
        self.path = path

    def __missing__(self, name):
        raise KeyError("%s: no column '%s' (it has %s)" % (self.path, name, ", ".join(self)))


def table_schema(path):
    """The schema the experiment wrote for the CSV at `path`: the entry of "tables" in the
    summary.json beside it whose "file" is the CSV's name ({"file", "rows", "columns": [{"name",
    "unit", "doc", "format", "csv"}]}), or None when there is none (a table no experiment wrote)."""
    summary = os.path.join(os.path.dirname(path), "summary.json")
    if not os.path.exists(summary):
        return None
    with open(summary) as f:
        tables = json.load(f).get("tables", {})
    for schema in tables.values():
        if schema.get("file") == os.path.basename(path):
            return schema
    return None


def schema_columns(schema):
    """The column names a schema puts in its CSV, in order."""
    return [c["name"] for c in schema["columns"] if c.get("csv", True)]


def check_against_schema(path, header, nrows):
    """ValueError naming the file when its header or row count is not what its schema says."""
    schema = table_schema(path)
    if schema is None:
        return
    want = schema_columns(schema)
    if header != want:
        raise ValueError("%s: header %s, but summary.json's schema says %s"
                         % (path, ",".join(header), ",".join(want)))
    if nrows != schema["rows"]:
        raise ValueError("%s: %d rows, but summary.json's schema says %d"
                         % (path, nrows, schema["rows"]))


def read_table(path):
    """Read a CSV of numbers (first row = names) into {column: [values]}; text cells stay text.
    When the experiment wrote the table's schema (summary.json "tables"), the header and the row
    count are checked against it, so a renamed column fails here, naming the file."""
    with open(path, newline="") as f:
        reader = csv.reader(f)
        header = next(reader)
        cols = {h: [] for h in header}
        nrows = 0
        for row in reader:
            nrows += 1
            for h, v in zip(header, row):
                try:
                    cols[h].append(float(v))
                except ValueError:
                    cols[h].append(v)
    check_against_schema(path, header, nrows)
    return TableColumns(path, cols)


def bones_from_trajectory(table, row):
    """The bones of one row of a trajectory table, in the bones-table form."""
    names = [c[:-len(".head_x")] for c in table if c.endswith(".head_x")]
    return [{
        "bone": n, "parent": "",
        "head": tuple(table["%s.head_%s" % (n, a)][row] for a in "xyz"),
        "tail": tuple(table["%s.tail_%s" % (n, a)][row] for a in "xyz"),
    } for n in names]


def draw_pose(ax, bones, view="front", color="k", label=None, alpha=1.0, targets=None):
    """Stick figure: one segment per bone, a dot at every joint; optional target crosses."""
    i, j, xl, yl = VIEWS[view]
    for k, b in enumerate(bones):
        ax.plot([b["head"][i], b["tail"][i]], [b["head"][j], b["tail"][j]], "-", color=color,
                lw=2, alpha=alpha, label=label if k == 0 else None, solid_capstyle="round")
        ax.plot([b["head"][i]], [b["head"][j]], "o", color=color, ms=3, alpha=alpha)
    if targets:
        for t in targets:
            ax.plot([t[i]], [t[j]], "x", color="tab:red", ms=8, mew=2)
    ax.set_xlabel(xl)
    ax.set_ylabel(yl)
    ax.set_aspect("equal", adjustable="datalim")
    ax.grid(True, lw=0.3)


def save(fig, path):
    os.makedirs(os.path.dirname(os.path.abspath(path)), exist_ok=True)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path


def plot_rest_pose(bones_csv, out_png, title=None):
    """Front and side views of one rig at rest (paper Fig 4 for pinhead)."""
    bones = read_bones_csv(bones_csv)
    fig, axes = plt.subplots(1, 2, figsize=(8, 5))
    for ax, view in zip(axes, ("front", "side")):
        draw_pose(ax, bones, view)
        ax.set_title(view)
    fig.suptitle(title or os.path.splitext(os.path.basename(bones_csv))[0])
    return save(fig, out_png)


def draw_boxes(ax, boxes, floor, view):
    """Static scenery under a stick figure: boxes (center, half_extents) as grey rectangles in the
    view's plane, a floor at height z as a grey line."""
    i, j, _, _ = VIEWS[view]
    for center, half in boxes:
        ax.add_patch(plt.Rectangle((center[i] - half[i], center[j] - half[j]), 2 * half[i],
                                   2 * half[j], color="0.8", zorder=0))
    if floor is not None:
        ax.axhline(floor, color="0.6", lw=1, zorder=0)


def pose_panels(panels, out_png, views=("front", "side"), suptitle=None, size=3.2):
    """A grid of stick figures: one row per view, one column per panel.

    panels: list of dicts {"bones": [...], "title": str, "targets": [(x,y,z)], "color": str,
            "overlay": [{"bones": [...], "color": str, "label": str}],
            "boxes": [(center, half_extents)] (axis-aligned static boxes, drawn as rectangles),
            "floor": z (a horizontal line)}
    """
    ncol = len(panels)
    fig, axes = plt.subplots(len(views), ncol, figsize=(size * ncol, size * len(views)), squeeze=False)
    for c, p in enumerate(panels):
        for r, view in enumerate(views):
            ax = axes[r][c]
            draw_boxes(ax, p.get("boxes", []), p.get("floor"), view)
            draw_pose(ax, p["bones"], view, color=p.get("color", "k"), label=p.get("label"),
                      targets=p.get("targets"))
            for o in p.get("overlay", []):
                draw_pose(ax, o["bones"], view, color=o.get("color", "tab:blue"), label=o.get("label"),
                          alpha=o.get("alpha", 0.8))
            if r == 0:
                ax.set_title(p.get("title", ""), fontsize=9)
            if p.get("label") or p.get("overlay"):
                ax.legend(fontsize=8, loc="best")
    if suptitle:
        fig.suptitle(suptitle)
    return save(fig, out_png)


def curves(series, out_png, xlabel, ylabel, title=None, logy=False, markers=None):
    """Line plot of several series: list of (x, y, label)."""
    fig, ax = plt.subplots(figsize=(6.4, 4.0))
    for k, (x, y, label) in enumerate(series):
        ax.plot(x, y, "-" if not markers else markers[k], label=label, lw=1.5, ms=4)
    if logy:
        ax.set_yscale("log")
    ax.set_xlabel(xlabel)
    ax.set_ylabel(ylabel)
    if title:
        ax.set_title(title)
    ax.grid(True, lw=0.3)
    if any(s[2] for s in series):
        ax.legend(fontsize=8)
    return save(fig, out_png)


def load_summary(folder):
    with open(os.path.join(folder, "summary.json")) as f:
        return json.load(f)


def pose_grid(rows, out_png, view="side", suptitle=None, size=2.6):
    """A grid of stick figures in one view: rows is a list of rows, each a list of panels
    {"bones", "title", "color", "targets"}."""
    nrow, ncol = len(rows), max(len(r) for r in rows)
    fig, axes = plt.subplots(nrow, ncol, figsize=(size * ncol, size * nrow), squeeze=False)
    for r, row in enumerate(rows):
        for c in range(ncol):
            ax = axes[r][c]
            if c >= len(row):
                ax.axis("off")
                continue
            p = row[c]
            draw_pose(ax, p["bones"], view, color=p.get("color", "k"), targets=p.get("targets"))
            ax.set_title(p.get("title", ""), fontsize=9)
    if suptitle:
        fig.suptitle(suptitle)
    return save(fig, out_png)


def same_limits(axes, poses, view, margin=0.2):
    """One equal-aspect window around all the poses for every axes (frames of one sequence on a
    common scale; matplotlib forbids datalim aspect on shared axes)."""
    i, j = {"front": (0, 2), "side": (1, 2)}[view]
    xs = [b[k][i] for bones in poses for b in bones for k in ("head", "tail")]
    ys = [b[k][j] for bones in poses for b in bones for k in ("head", "tail")]
    cx, cy = 0.5 * (min(xs) + max(xs)), 0.5 * (min(ys) + max(ys))
    half = 0.5 * max(max(xs) - min(xs), max(ys) - min(ys)) + margin
    for ax in axes:
        ax.set_aspect("equal", adjustable="box")
        ax.set_xlim(cx - half, cx + half)
        ax.set_ylim(cy - half, cy + half)
