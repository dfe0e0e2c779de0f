#!/usr/bin/python3
"""models/highway/conflict_map.py's layout: a long road in segments, each conflict (a row of
conflicts.csv) drawn once, a north-south road turned (not mirrored), a square network one
equal-aspect panel; TTC* from the run's summary.json in the title; a warnings.csv refused. Exits 77
(skipped) without matplotlib."""
import csv
import json
import os
import random
import re
import subprocess
import sys
import tempfile
import unittest

SRC = os.environ.get("STSIM_SOURCE_DIR", os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", ".."))
SCRIPT = os.path.join(SRC, "models", "highway", "conflict_map.py")

try:
    import matplotlib  # noqa: F401
except ImportError:
    print("python3-matplotlib not installed: skipped")
    sys.exit(77)


def markers(svg, prefix="conflicts_"):
    """Markers inside the conflicts_* groups (as tests/svg_markers.hpp counts them), or another
    prefix's (a junction panel's junction_*)."""
    n = 0
    for m in re.finditer(r'<g id="%s' % prefix, svg):
        depth, i = 0, m.start()
        while True:
            o, c = svg.find("<g", i + 1), svg.find("</g>", i + 1)
            if o != -1 and o < c:
                depth, i = depth + 1, o
            elif depth == 0:
                end = c
                break
            else:
                depth, i = depth - 1, c
        group = re.sub(r"<defs>.*?</defs>", "", svg[m.start():end], flags=re.S)
        n += group.count("<use ") + group.count("<path ")
    return n


TYPES = ["rear_end", "lane_change", "crossing"]


def write_conflicts(path, points):
    """conflicts.csv's columns the map reads; a point without (x, y) has only the two centres; a
    point's fourth field, if any, is its junction."""
    with open(path, "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["first", "second", "type", "max_delta_v", "conflict_x", "conflict_y",
                    "first_x", "first_y", "second_x", "second_y", "junction"])
        for i, (x, y, t, *j) in enumerate(points):
            w.writerow(["a.%d" % i, "b.%d" % i, t, 5.0, x, y, x - 2.0, y, x + 2.0, y, j[0] if j else ""])


def draw(tmp, name, points, summary=None, net=None):
    d = os.path.join(tmp, name)
    os.makedirs(d)
    csv_path = os.path.join(d, "conflicts.csv")
    write_conflicts(csv_path, points)
    if summary is not None:
        with open(os.path.join(d, "summary.json"), "w") as f:
            json.dump(summary, f)
    out = os.path.join(tmp, name)
    subprocess.run(["/usr/bin/python3", SCRIPT, "--out", out, "--title", name, csv_path]
                   + (["--net", net] if net else []), check=True)
    with open(out + ".svg") as f:
        return f.read()


class ConflictMapLayout(unittest.TestCase):
    def setUp(self):
        self.tmp = tempfile.mkdtemp(prefix="stsim_map_test_")
        random.seed(3)

    def road(self, along_x, n=240, length=3000.0):
        pts = []
        for i in range(n):
            s, c = random.uniform(0, length), random.choice([0.0, 3.5, 7.0])
            t = random.choice(TYPES)
            pts.append((s, -c, t) if along_x else (c, s, t))
        # on the cuts between segments (3000 / 4): each drawn once
        pts += [(750.0, 0.0, "rear_end"), (1500.0, 0.0, "rear_end"), (3000.0, 0.0, "rear_end")] \
            if along_x else [(0.0, 750.0, "rear_end"), (0.0, 2250.0, "rear_end")]
        return pts

    def test_a_long_road_is_cut_into_segments_and_every_conflict_drawn_once(self):
        pts = self.road(True)
        svg = draw(self.tmp, "east_west", pts)
        self.assertEqual(markers(svg), len(pts))
        self.assertIn("in 4 segments along x", svg)
        # every segment has its own groups, numbered by panel
        self.assertTrue(re.search(r'id="conflicts_\w+_4"', svg))

    def test_a_north_south_road_is_turned_not_mirrored(self):
        import importlib.util
        spec = importlib.util.spec_from_file_location("conflict_map", SCRIPT)
        cm = importlib.util.module_from_spec(spec)
        spec.loader.exec_module(cm)
        pts = self.road(False)
        svg = draw(self.tmp, "north_south", pts)
        self.assertEqual(markers(svg), len(pts))
        self.assertIn("segments along y", svg)
        # the layout's panels run along y; the drawn axes turn a quarter clockwise: the lateral
        # (x) axis points down, so east is below and the picture is a rotation, not a reflection
        panels, axis, stretch, cuts = cm.layout([], [(x, y, t, 0.0) for x, y, t in pts])
        self.assertEqual(axis, "y")
        self.assertGreater(stretch, 1.0)
        self.assertEqual(len(cuts), len(panels))
        # two marked conflicts at one northing: the eastern one (x = 7) is drawn below the western
        # one (x = 0), as a quarter turn clockwise puts it (a mirror would draw it above)
        road = [(random.choice([0.0, 3.5, 7.0]), random.uniform(0, 3000), "rear_end") for _ in range(100)]
        svg = draw(self.tmp, "turned", road + [(7.0, 100.0, "crossing"), (0.0, 100.0, "lane_change")])

        def screen_y(kind):
            group = re.search(r'<g id="conflicts_%s_1">(.*?)</g>' % kind, svg, flags=re.S).group(1)
            return float(re.search(r'<use [^>]*\by="([-0-9.]+)"', group).group(1))
        self.assertGreater(screen_y("crossing"), screen_y("lane_change"))  # SVG's y grows downwards

    def test_a_square_network_is_one_panel_at_equal_scales(self):
        pts = [(random.uniform(0, 300), random.uniform(0, 300), "crossing") for _ in range(50)]
        svg = draw(self.tmp, "square", pts)
        self.assertEqual(markers(svg), len(pts))
        self.assertNotIn("segments", svg)

    def test_a_junction_small_beside_the_network_gets_its_own_panel(self):
        # the crosswalk network: 400 m across, junction C's outline 31 m; the conflicts within 12 m
        # of it drawn again in C's panel, the others (on the arms) only in the whole
        net = os.path.join(SRC, "networks", "crosswalk", "crosswalk.net.xml")
        at_c = [(random.uniform(-14, 14), random.uniform(-14, 14), random.choice(TYPES + ["pedestrian"]))
                for _ in range(30)]
        arms = [(random.uniform(40, 150), random.choice([-1.6, 1.6]), "rear_end") for _ in range(10)]
        svg = draw(self.tmp, "junction", at_c + arms, net=net)
        self.assertEqual(markers(svg), 40)
        self.assertEqual(markers(svg, "junction_C_"), 30)
        self.assertIn("around junction C: 30 conflicts", svg)
        # no network: no outline to zoom to, one panel as before
        svg = draw(self.tmp, "junction_no_net", at_c + arms)
        self.assertEqual(markers(svg), 40)
        self.assertEqual(markers(svg, "junction_"), 0)
        # conflicts only on the arms, none within a junction's window (C's, or the dead ends' 200 m out): no panel
        svg = draw(self.tmp, "junction_none", arms, net=net)
        self.assertEqual(markers(svg, "junction_"), 0)

    def test_one_point_per_conflicts_row_and_ttc_star_from_the_summary(self):
        pts = [(random.uniform(0, 300), random.uniform(0, 300), random.choice(TYPES)) for _ in range(37)]
        svg = self.draw_with_centres("ttc", pts, summary={"conflicts": {"max_ttc_s": 2.5}})
        rows = len(pts) + 1  # and the row without a conflict point
        self.assertEqual(markers(svg), rows)
        self.assertIn("%d conflicts at TTC* 2.5 s" % rows, svg)
        self.assertIn("rear-end (%d)" % (sum(1 for p in pts if p[2] == "rear_end") + 1), svg)
        # no summary.json: TTC* named, its value unknown
        svg = draw(self.tmp, "no_summary", pts)
        self.assertIn("%d conflicts at TTC* (" % len(pts), svg)

    def draw_with_centres(self, name, pts, summary):
        """draw() plus one row whose conflict point is empty (its centres at 10, 10 and 14, 10)."""
        d = os.path.join(self.tmp, name)
        os.makedirs(d)
        path = os.path.join(d, "conflicts.csv")
        write_conflicts(path, pts)
        with open(path, "a", newline="") as f:
            csv.writer(f).writerow(["c", "d", "rear_end", 1.0, "", "", 10.0, 10.0, 14.0, 10.0])
        with open(os.path.join(d, "summary.json"), "w") as f:
            json.dump(summary, f)
        out = os.path.join(self.tmp, name)
        subprocess.run(["/usr/bin/python3", SCRIPT, "--out", out, path], check=True)
        with open(out + ".svg") as f:
            return f.read()

    def test_a_warnings_csv_is_refused(self):
        path = os.path.join(self.tmp, "warnings.csv")
        with open(path, "w", newline="") as f:
            w = csv.writer(f)
            w.writerow(["ego", "foe", "kind", "x", "y", "type", "max_delta_v"])
            w.writerow(["a", "curb", "curb", 1.0, 2.0, "road", ""])
        r = subprocess.run(["/usr/bin/python3", SCRIPT, "--out", os.path.join(self.tmp, "w"), path],
                           capture_output=True, text=True)
        self.assertEqual(r.returncode, 1)
        self.assertIn("not a conflicts.csv", r.stdout)
        self.assertFalse(os.path.exists(os.path.join(self.tmp, "w.png")))


if __name__ == "__main__":
    unittest.main()
