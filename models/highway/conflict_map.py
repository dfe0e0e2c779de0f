#!/usr/bin/python3
"""A conflict map: the network's lanes and every conflict of conflicts.csv (one row, one point: an
unordered pair's continuous encounter with TTC at most TTC*) at its conflict point, coloured by
type (SSAM's rear-end, lane change, crossing; a vehicle with a person: pedestrian), sized by MaxDeltaV. Warnings (per ego, against each
car's safe time, road warnings among them) are not drawn: they are what a driver gets, not what a
safety study counts. TTC* is read from the summary.json beside each conflicts.csv (its
conflicts.max_ttc_s), or given with --ttc-star, and said in the title. A long thin network (a
motorway) is cut into segments along its length, one panel each, the lateral scale stretched (said
in the title) so that its lanes show apart. On a network with junctions small beside it (a
--net's junction outlines), the junctions with the most conflicts around them (up to three) get a
panel each at a readable scale beside the whole, with internal lanes, crosswalks and walking areas.

Uses Debian's python3-matplotlib. Called by `stsim highway` and `stsim batch`; by hand:
    /usr/bin/python3 models/highway/conflict_map.py --out PREFIX [--net NET.net.xml] [--title T] \
        [--ttc-star S] conflicts.csv [conflicts.csv ...]
writes PREFIX.png and PREFIX.svg. In the SVG each conflict is one <use> marker inside a group whose
id starts with "conflicts_" (one group per type and panel), so the markers can be counted (a
junction panel's groups start with "junction_": the same conflicts again, closer). A file
that is not a conflicts.csv (a warnings.csv) is refused (exit 1).
"""
import argparse
import csv
import json
import math
import os
import sys
import xml.etree.ElementTree as ET

try:
    import matplotlib
except ImportError:
    # stsim tells a missing tool (no map, the run is fine) from a failed map (exit 1) by this code
    print("python3-matplotlib is not installed (apt-get install python3-matplotlib)")
    sys.exit(3)

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
from matplotlib.collections import LineCollection  # noqa: E402
from matplotlib.lines import Line2D  # noqa: E402
from matplotlib.patches import Polygon, Rectangle  # noqa: E402

# type -> (label, colour); the order of the legend: SSAM's three angle classes and a vehicle with
# a person on foot, all conflicts.csv has
TYPES = [
    ("rear_end", "rear-end", "#d62728"),
    ("lane_change", "lane change", "#ff7f0e"),
    ("crossing", "crossing", "#1f77b4"),
    ("pedestrian", "pedestrian", "#2ca02c"),
]
# marker area (pt^2) at severity 0 and per m/s, capped
SIZE0, SIZE_PER_MS, SIZE_MAX = 6.0, 6.0, 160.0
# the columns that make a file a conflicts.csv (a warnings.csv has none of the first two)
CONFLICT_COLUMNS = ("first", "second", "type", "conflict_x", "conflict_y")


def num(s):
    try:
        v = float(s)
        return v if math.isfinite(v) else None
    except (TypeError, ValueError):
        return None


def shape_of(text):
    pts = []
    for p in (text or "").split():
        xy = p.split(",")
        if len(xy) >= 2:
            pts.append((float(xy[0]), float(xy[1])))
    return pts


def read_network(path):
    """The lanes' centre lines ((points, internal) per lane, crossings and walking areas left out),
    the crossings' and walking areas' shapes, and each junction's outline by id (not the internal
    ones)."""
    lanes, crossings, walking, junctions = [], [], [], {}
    function = ""
    for _, el in ET.iterparse(path, events=("start",)):
        if el.tag == "edge":
            function = el.get("function") or ""
        elif el.tag == "lane" and el.get("shape"):
            pts = shape_of(el.get("shape"))
            if len(pts) < 2:
                continue
            if function == "crossing":
                crossings.append(pts)
            elif function == "walkingarea":
                walking.append(pts)
            else:
                lanes.append((pts, function == "internal"))
        elif el.tag == "junction" and el.get("type") != "internal" and el.get("shape"):
            junctions[el.get("id")] = shape_of(el.get("shape"))
    return lanes, crossings, walking, junctions


class NotConflicts(Exception):
    pass


def read_conflicts(paths):
    """One (x, y, type, MaxDeltaV) per row of each conflicts.csv: at its conflict point, else (a
    row without one) midway between the two vehicles' centres, so every conflict is drawn once."""
    out = []
    for path in paths:
        with open(path, newline="") as f:
            rows = csv.DictReader(f)
            missing = [c for c in CONFLICT_COLUMNS if c not in (rows.fieldnames or [])]
            if missing:
                raise NotConflicts("%s is not a conflicts.csv (no %s column): the map draws conflicts, "
                                   "not warnings" % (path, ", ".join(missing)))
            for c in rows:
                x, y = num(c.get("conflict_x")), num(c.get("conflict_y"))
                if x is None or y is None:
                    xs = [num(c.get("first_x")), num(c.get("second_x"))]
                    ys = [num(c.get("first_y")), num(c.get("second_y"))]
                    if None in xs or None in ys:
                        raise NotConflicts("%s: conflict %s/%s has no position" % (path, c["first"], c["second"]))
                    x, y = sum(xs) / 2.0, sum(ys) / 2.0
                out.append((x, y, c.get("type") or "", max(0.0, num(c.get("max_delta_v")) or 0.0)))
    return out


def ttc_stars(paths):
    """TTC* of each conflicts.csv's run, from its summary.json (conflicts.max_ttc_s); None where
    there is none."""
    stars = []
    for path in paths:
        v = None
        try:
            with open(os.path.join(os.path.dirname(os.path.abspath(path)), "summary.json")) as f:
                v = num((json.load(f).get("conflicts") or {}).get("max_ttc_s"))
        except (OSError, ValueError, AttributeError):
            pass
        stars.append(v)
    return stars


def threshold_text(stars):
    """'TTC* 1.5 s' for the title; several values listed; 'TTC*' alone when none is known."""
    known = sorted(set(s for s in stars if s is not None))
    if not known:
        return "TTC*"
    return "TTC* " + " / ".join("%g" % s for s in known) + " s"


# a network longer than this many times its width is cut into segments
SEGMENT_ASPECT = 6.0
SEGMENT_LENGTH = 800.0  # m, about; at most MAX_SEGMENTS
MAX_SEGMENTS = 6
PANEL_RATIO = 0.14  # a segment's panel: height over width, before the lateral stretch is capped


def layout(lanes, points):
    """The panels: [(long range, cross range)] along the network's long axis, the axis ('x' or
    'y') and the lateral stretch (1: equal scales, a single panel)."""
    xs = [p[0] for pts, _ in lanes for p in pts] + [w[0] for w in points]
    ys = [p[1] for pts, _ in lanes for p in pts] + [w[1] for w in points]
    if not xs:
        return [((0.0, 1.0), (0.0, 1.0))], "x", 1.0, [math.inf]
    span_x, span_y = max(xs) - min(xs), max(ys) - min(ys)
    axis = "x" if span_x >= span_y else "y"
    along, across = (xs, ys) if axis == "x" else (ys, xs)
    lo, hi = min(along), max(along)
    long_span, short_span = hi - lo, max(min(span_x, span_y), 1.0)
    if long_span / short_span < SEGMENT_ASPECT:
        pad = 0.03 * max(span_x, span_y, 1.0)
        # one panel, never turned: x across, y up
        return [((min(xs) - pad, max(xs) + pad), (min(ys) - pad, max(ys) + pad))], "x", 1.0, [math.inf]
    k = int(min(MAX_SEGMENTS, max(2, math.ceil(long_span / SEGMENT_LENGTH))))
    step = long_span / k
    lane_pts = [(p[0], p[1]) if axis == "x" else (p[1], p[0]) for pts, _ in lanes for p in pts]
    pts = [(w[0], w[1]) if axis == "x" else (w[1], w[0]) for w in points]
    panels, cuts = [], []  # cuts: each panel's upper end along the axis; a point is in the first it is below
    for i in range(k):
        a, b = lo + i * step, lo + (i + 1) * step
        inside = [c for (l, c) in pts if a <= l <= b] or [c for (l, c) in lane_pts if a <= l <= b] or across
        # the points' lateral extent, or the lanes' where there are none, with a lane or two beside
        c0, c1 = min(inside) - 10.0, max(inside) + 10.0
        pad = 0.01 * step
        panels.append(((a - pad, b + pad), (c0, c1)))
        cuts.append(b)
    stretch = max(1.0, min(PANEL_RATIO * step / (c1 - c0) for _, (c0, c1) in panels))
    return panels, axis, stretch, cuts



# junction panels: at most this many (the busiest), each showing this much around the junction
MAX_JUNCTIONS = 3
JUNCTION_MARGIN = 12.0  # m
JUNCTION_SMALL = 0.25   # a junction gets a panel when its window spans less than this share of the whole


def junction_windows(junctions, points, whole):
    """[(junction id, ((x0, x1), (y0, y1)))]: the junctions with the most conflicts in their window
    (the outline, square, with a margin), those windows small beside the whole map; a junction
    whose centre lies in a window already taken is left out (a roundabout's entries, say, stay
    apart only if their windows do)."""
    (wx0, wx1), (wy0, wy1) = whole
    span = max(wx1 - wx0, wy1 - wy0, 1.0)
    found = []
    for j, shape in junctions.items():
        xs, ys = [p[0] for p in shape], [p[1] for p in shape]
        cx, cy = (min(xs) + max(xs)) / 2.0, (min(ys) + max(ys)) / 2.0
        half = max(max(xs) - min(xs), max(ys) - min(ys)) / 2.0 + JUNCTION_MARGIN
        if 2.0 * half >= JUNCTION_SMALL * span:
            continue
        n = sum(1 for w in points if abs(w[0] - cx) <= half and abs(w[1] - cy) <= half)
        if n:
            found.append((-n, j, cx, cy, half))
    out = []
    for _, j, cx, cy, half in sorted(found):
        if len(out) == MAX_JUNCTIONS:
            break
        if any(x0 <= cx <= x1 and y0 <= cy <= y1 for _, ((x0, x1), (y0, y1)) in out):
            continue
        out.append((j, ((cx - half, cx + half), (cy - half, cy + half))))
    return out


def size_of(sev):
    return min(SIZE_MAX, SIZE0 + SIZE_PER_MS * sev)


def main(argv):
    ap = argparse.ArgumentParser(description="conflict map of stsim's conflicts.csv")
    ap.add_argument("--out", required=True, help="output prefix (writes PREFIX.png and PREFIX.svg)")
    ap.add_argument("--net", help="SUMO .net.xml whose lanes are drawn")
    ap.add_argument("--title", default="")
    ap.add_argument("--ttc-star", type=float, help="TTC* (s) to name in the title (default: the runs' summary.json)")
    ap.add_argument("csv", nargs="+", help="conflicts.csv files, drawn together")
    a = ap.parse_args(argv)

    try:
        conflicts = read_conflicts(a.csv)
    except NotConflicts as e:
        print(e)
        return 1
    threshold = threshold_text([a.ttc_star] if a.ttc_star is not None else ttc_stars(a.csv))
    # a type conflicts.csv does not write today still gets its points, in grey
    types = TYPES + [(t, t.replace("_", " "), "#7f7f7f")
                     for t in sorted(set(w[2] for w in conflicts) - set(k for k, _, _ in TYPES))]
    lanes, crossings, walking, junctions = read_network(a.net) if a.net else ([], [], [], {})
    panels, axis, stretch, cuts = layout(lanes, conflicts)
    flip = axis == "y"  # a north-south network: its length along the panels' horizontal axis (turned)
    windows = junction_windows(junctions, conflicts, panels[0]) if len(panels) == 1 else []
    zooms = []
    if windows:
        # the whole at its own shape on the left, the junctions stacked on the right, the legend
        # inside the whole (the junctions' panels take the space beside it)
        fig = plt.figure(figsize=(12.6, max(6.4, 3.2 * len(windows))))
        gs = fig.add_gridspec(len(windows), 2, width_ratios=[1.75, 1.0])
        axes = [fig.add_subplot(gs[:, 0])]
        zooms = [fig.add_subplot(gs[k, 1]) for k in range(len(windows))]
    elif len(panels) == 1:
        # one panel at the network's own shape, the legend to its right
        (l0, l1), (c0, c1) = panels[0]
        fig, ax = plt.subplots(figsize=(9.2, max(2.6, min(7.0, 7.0 * (c1 - c0) / max(l1 - l0, 1.0) + 1.0))))
        axes = [ax]
    else:
        # segments stacked, each exactly as tall as its stretched lateral range (placed by hand:
        # an aspect-locked panel in a grid leaves gaps)
        left, aw, top, gap, bottom = 0.7, 6.2, 0.6, 0.45, 0.5
        hs = [aw * (c1 - c0) * stretch / (l1 - l0) for (l0, l1), (c0, c1) in panels]
        fw, fh = 9.4, top + sum(hs) + gap * (len(hs) - 1) + bottom
        fig = plt.figure(figsize=(fw, fh))
        axes, y = [], fh - top
        for h in hs:
            y -= h
            axes.append(fig.add_axes([left / fw, y / fh, aw / fw, h / fh]))
            y -= gap

    def xy(x, y):
        return (y, x) if flip else (x, y)

    def panel_of(along):
        for j, cut in enumerate(cuts):
            if along < cut:
                return j
        return len(cuts) - 1

    counts = {key: sum(1 for w in conflicts if w[2] == key) for key, _, _ in types}
    for i, (ax, ((l0, l1), (c0, c1))) in enumerate(zip(axes, panels)):
        if lanes:
            normal = [[xy(*p) for p in pts] for pts, internal in lanes if not internal]
            inner = [[xy(*p) for p in pts] for pts, internal in lanes if internal]
            ax.add_collection(LineCollection(normal, colors="#b0b0b0", linewidths=1.2, zorder=1))
            ax.add_collection(LineCollection(inner, colors="#d0d0d0", linewidths=0.6, zorder=1))
        last = i == len(panels) - 1
        for key, label, colour in types:
            # each conflict in one panel: the last takes its upper end
            pts = [w for w in conflicts if w[2] == key and panel_of(xy(w[0], w[1])[0]) == i]
            if not pts:
                continue
            # the most severe drawn last (on top)
            pts.sort(key=lambda w: w[3])
            p = [xy(w[0], w[1]) for w in pts]
            sc = ax.scatter([q[0] for q in p], [q[1] for q in p], s=[size_of(w[3]) for w in pts],
                            facecolors=colour, edgecolors="black", alpha=0.65, linewidths=0.3, zorder=3)
            sc.set_gid("conflicts_%s_%d" % (key, i + 1))
        ax.set_xlim(l0, l1)
        # a north-south network turned a quarter clockwise (north to the right, east down), not
        # mirrored: left and right of the traffic stay where they are
        ax.set_ylim((c1, c0) if flip else (c0, c1))
        ax.set_aspect(stretch if len(panels) > 1 else "equal", adjustable="box" if len(panels) > 1 else "datalim")
        ax.grid(alpha=0.2)
        ax.tick_params(labelsize=7)
        ax.set_ylabel("%s (m)" % ("x" if flip else "y"), fontsize=8)
        if last:
            ax.set_xlabel("%s (m)" % ("y" if flip else "x"), fontsize=8)
    for zx, (j, ((x0, x1), (y0, y1))) in zip(zooms, windows):
        for pts in walking:
            zx.add_patch(Polygon(pts, closed=True, facecolor="#eeeeee", edgecolor="none", zorder=0))
        zx.add_patch(Polygon(junctions[j], closed=True, facecolor="none", edgecolor="#c8c8c8",
                             linewidth=0.6, zorder=0))
        zx.add_collection(LineCollection(crossings, colors="#dcdcdc", linewidths=7.0, zorder=0))
        zx.add_collection(LineCollection([pts for pts, internal in lanes if not internal], colors="#b0b0b0",
                                         linewidths=1.2, zorder=1))
        zx.add_collection(LineCollection([pts for pts, internal in lanes if internal], colors="#c0c0c0",
                                         linewidths=0.7, zorder=1))
        here = {}
        for key, label, colour in types:
            pts = sorted((w for w in conflicts if w[2] == key and x0 <= w[0] <= x1 and y0 <= w[1] <= y1),
                         key=lambda w: w[3])
            if not pts:
                continue
            here[label] = len(pts)
            sc = zx.scatter([w[0] for w in pts], [w[1] for w in pts], s=[size_of(w[3]) for w in pts],
                            facecolors=colour, edgecolors="black", alpha=0.65, linewidths=0.3, zorder=3)
            sc.set_gid("junction_%s_%s" % (j, key))
        zx.set_xlim(x0, x1)
        zx.set_ylim(y0, y1)
        zx.set_aspect("equal", adjustable="datalim")
        zx.grid(alpha=0.2)
        zx.tick_params(labelsize=7)
        zx.set_title("around junction %s: %d conflicts (%s)" % (j, sum(here.values()),
                                                         ", ".join("%d %s" % (n, l) for l, n in here.items())),
                     fontsize=8)
        # where it lies in the whole
        axes[0].add_patch(Rectangle((x0, y0), x1 - x0, y1 - y0, fill=False,
                                    edgecolor="#555555", linewidth=0.6, linestyle="--", zorder=2))
        axes[0].annotate(j, (x1, y1), fontsize=7, color="#555555", xytext=(2, 2), textcoords="offset points")
    # the legend: types (with counts) and three sizes, from proxy handles (not counted as conflicts)
    handles = [Line2D([], [], linestyle="none", marker="o", markersize=7, markerfacecolor=colour,
                      markeredgecolor="black", markeredgewidth=0.3, alpha=0.8,
                      label="%s (%d)" % (label, counts[key])) for key, label, colour in types if counts[key]]
    for sev in (2.0, 10.0, 20.0):
        handles.append(Line2D([], [], linestyle="none", marker="o", markersize=math.sqrt(size_of(sev)),
                              markerfacecolor="white", markeredgecolor="black", markeredgewidth=0.5,
                              label="%g m/s" % sev))
    where = dict(loc="lower left") if zooms else dict(loc="upper left", bbox_to_anchor=(1.01, 1.0))
    leg = axes[0].legend(handles=handles, **where, fontsize=7,
                         framealpha=0.85, title="conflicts at %s\n(conflicts.csv; no warnings)\n"
                         "type; size: MaxΔV" % threshold, title_fontsize=7)
    leg.set_gid("legend")
    title = (a.title + ": " if a.title else "") + "%d conflicts at %s (%s)" % (
        len(conflicts), threshold, ", ".join("%d %s" % (counts[k], l) for k, l, _ in types if counts[k]) or "none")
    if len(panels) > 1:
        title += "\nin %d segments along %s; lateral scale stretched %.0f×" % (len(panels), axis, stretch) \
            if stretch > 1.0 else "\nin %d segments along %s" % (len(panels), axis)
    axes[0].set_title(title, fontsize=9)
    if len(panels) == 1:
        fig.tight_layout()
    fig.savefig(a.out + ".png", dpi=100)
    fig.savefig(a.out + ".svg")
    plt.close(fig)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
