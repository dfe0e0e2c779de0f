#!/usr/bin/python3
"""A conflict map: the network's lanes and every warning at its position, coloured by conflict type,
sized by severity (vehicle warnings: MaxDeltaV; road warnings: the lateral speed towards the line).

Uses Debian's python3-matplotlib. Called by `stsim highway` and `stsim batch`; by hand:
    /usr/bin/python3 models/highway/conflict_map.py --out PREFIX [--net NET.net.xml] [--title T] \
        warnings.csv [warnings.csv ...]
writes PREFIX.png and PREFIX.svg. In the SVG each warning is one <use> marker inside a group whose
id starts with "warnings_" (one group per type), so the markers can be counted.
"""
import argparse
import csv
import math
import sys
import xml.etree.ElementTree as ET

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
from matplotlib.collections import LineCollection  # noqa: E402
from matplotlib.lines import Line2D  # noqa: E402

# type -> (label, colour); the order of the legend
TYPES = [
    ("rear_end", "rear-end", "#d62728"),
    ("lane_change", "lane change", "#ff7f0e"),
    ("crossing", "crossing", "#1f77b4"),
    # none of SSAM's conflicts: a zone occupied (or reached) without the bodies on a collision course
    ("proximity", "proximity (no collision course)", "#9467bd"),
    ("road", "road (curb, marker, hazard)", "#7f7f7f"),
]
# drawn underneath and fainter, so the conflicts show
FAINT = ("proximity", "road")
# marker area (pt^2) at severity 0 and per m/s, capped
SIZE0, SIZE_PER_MS, SIZE_MAX = 6.0, 6.0, 160.0


def num(s):
    try:
        v = float(s)
        return v if math.isfinite(v) else None
    except (TypeError, ValueError):
        return None


def read_lanes(path):
    """Centre lines of the network's lanes: (points, internal) per lane."""
    lanes = []
    internal_edge = False
    for _, el in ET.iterparse(path, events=("start",)):
        if el.tag == "edge":
            internal_edge = el.get("function") == "internal"
        elif el.tag == "lane" and el.get("shape"):
            pts = []
            for p in el.get("shape").split():
                xy = p.split(",")
                if len(xy) >= 2:
                    pts.append((float(xy[0]), float(xy[1])))
            if len(pts) >= 2:
                lanes.append((pts, internal_edge))
    return lanes


def read_warnings(paths):
    out = []
    for path in paths:
        with open(path, newline="") as f:
            for w in csv.DictReader(f):
                x, y = num(w.get("x")), num(w.get("y"))
                if x is None or y is None:
                    continue
                t = w.get("type") or "road"
                sev = num(w.get("max_delta_v")) if t != "road" else num(w.get("lateral_speed"))
                out.append((x, y, t, max(0.0, sev or 0.0)))
    return out


def size_of(sev):
    return min(SIZE_MAX, SIZE0 + SIZE_PER_MS * sev)


def main(argv):
    ap = argparse.ArgumentParser(description="conflict map of stsim warnings")
    ap.add_argument("--out", required=True, help="output prefix (writes PREFIX.png and PREFIX.svg)")
    ap.add_argument("--net", help="SUMO .net.xml whose lanes are drawn")
    ap.add_argument("--title", default="")
    ap.add_argument("csv", nargs="+")
    a = ap.parse_args(argv)

    warnings = read_warnings(a.csv)
    lanes = read_lanes(a.net) if a.net else []
    xs = [p[0] for pts, _ in lanes for p in pts] + [w[0] for w in warnings]
    ys = [p[1] for pts, _ in lanes for p in pts] + [w[1] for w in warnings]
    # the figure takes the network's shape (a motorway is a wide strip), the legend to its right
    span_x = max(xs) - min(xs) if xs else 1.0
    span_y = max(ys) - min(ys) if ys else 1.0
    aspect = max(span_y, 1.0) / max(span_x, 1.0)
    width = 7.0
    fig, ax = plt.subplots(figsize=(width + 2.2, max(2.6, min(7.0, width * aspect + 1.0))))
    if lanes:
        normal = [pts for pts, internal in lanes if not internal]
        inner = [pts for pts, internal in lanes if internal]
        ax.add_collection(LineCollection(normal, colors="#b0b0b0", linewidths=1.2, zorder=1))
        ax.add_collection(LineCollection(inner, colors="#d0d0d0", linewidths=0.6, zorder=1))
    counts = {}
    for key, label, colour in TYPES:
        pts = [w for w in warnings if w[2] == key]
        counts[key] = len(pts)
        if not pts:
            continue
        # the most severe drawn last (on top)
        pts.sort(key=lambda w: w[3])
        # road and proximity warnings (often the most) underneath and fainter, so the conflicts show
        faint = key in FAINT
        sc = ax.scatter([w[0] for w in pts], [w[1] for w in pts], s=[size_of(w[3]) for w in pts],
                        c=colour, alpha=0.3 if faint else 0.65, linewidths=0.3, edgecolors="black",
                        zorder=2 if faint else 3)
        sc.set_gid("warnings_" + key)
    # the legend: types (with counts) and three sizes, from proxy handles (not counted as warnings)
    handles = [Line2D([], [], linestyle="none", marker="o", markersize=7, markerfacecolor=colour,
                      markeredgecolor="black", markeredgewidth=0.3, alpha=0.8,
                      label="%s (%d)" % (label, counts[key])) for key, label, colour in TYPES if counts[key]]
    for sev in (2.0, 10.0, 20.0):
        handles.append(Line2D([], [], linestyle="none", marker="o", markersize=math.sqrt(size_of(sev)),
                              markerfacecolor="white", markeredgecolor="black", markeredgewidth=0.5,
                              label="%g m/s" % sev))
    if handles:
        leg = ax.legend(handles=handles, loc="upper left", bbox_to_anchor=(1.01, 1.0), fontsize=7, framealpha=0.85,
                        title="type; size: ΔV\n(road: lateral speed)", title_fontsize=7)
        leg.set_gid("legend")
    if xs:
        pad = 0.03 * max(max(xs) - min(xs), max(ys) - min(ys), 1.0)
        ax.set_xlim(min(xs) - pad, max(xs) + pad)
        ax.set_ylim(min(ys) - pad, max(ys) + pad)
    ax.set_aspect("equal", adjustable="datalim")
    ax.set_xlabel("x (m)")
    ax.set_ylabel("y (m)")
    conflicts = sum(counts[k] for k in ("rear_end", "lane_change", "crossing"))
    ax.set_title((a.title + ": " if a.title else "") + "%d warnings: %d conflicts, %d proximity, %d road"
                 % (len(warnings), conflicts, counts["proximity"], counts["road"]), fontsize=9)
    ax.grid(alpha=0.2)
    fig.tight_layout()
    fig.savefig(a.out + ".png", dpi=100)
    fig.savefig(a.out + ".svg")
    plt.close(fig)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
