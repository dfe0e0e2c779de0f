#!/usr/bin/python3
"""models/highway/conflict_map.py's layout: a long road in segments, each warning drawn once, a
north-south road turned (not mirrored), a square network one equal-aspect panel. Exits 77
(skipped) without matplotlib."""
import csv
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


def markers(svg):
    """Markers inside the warnings_* groups (as tests/svg_markers.hpp counts them)."""
    n = 0
    for m in re.finditer(r'<g id="warnings_', svg):
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


def write_warnings(path, points):
    with open(path, "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["x", "y", "type", "max_delta_v", "lateral_speed", "verdict"])
        for x, y, t, verdict in points:
            w.writerow([x, y, t, 5.0, "", verdict])


def draw(tmp, name, points):
    csv_path = os.path.join(tmp, name + ".csv")
    write_warnings(csv_path, points)
    out = os.path.join(tmp, name)
    subprocess.run(["/usr/bin/python3", SCRIPT, "--out", out, "--title", name, csv_path], check=True)
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
            t = random.choice(["rear_end", "lane_change", "proximity", "road"])
            v = random.choice(["confirmed", "nuisance", ""])
            pts.append((s, -c, t, v) if along_x else (c, s, t, v))
        # on the cuts between segments (3000 / 4): each drawn once
        pts += [(750.0, 0.0, "rear_end", ""), (1500.0, 0.0, "rear_end", ""), (3000.0, 0.0, "rear_end", "")] \
            if along_x else [(0.0, 750.0, "rear_end", ""), (0.0, 2250.0, "rear_end", "")]
        return pts

    def test_a_long_road_is_cut_into_segments_and_every_warning_drawn_once(self):
        pts = self.road(True)
        svg = draw(self.tmp, "east_west", pts)
        self.assertEqual(markers(svg), len(pts))
        self.assertIn("in 4 segments along x", svg)
        # every segment has its own groups, numbered by panel
        self.assertTrue(re.search(r'id="warnings_\w+_4"', svg))

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
        panels, axis, stretch, cuts = cm.layout([], [(x, y, t, 0.0, False) for x, y, t, _ in pts])
        self.assertEqual(axis, "y")
        self.assertGreater(stretch, 1.0)
        self.assertEqual(len(cuts), len(panels))
        # two marked warnings at one northing: the eastern one (x = 7) is drawn below the western
        # one (x = 0), as a quarter turn clockwise puts it (a mirror would draw it above)
        road = [(random.choice([0.0, 3.5, 7.0]), random.uniform(0, 3000), "proximity", "") for _ in range(100)]
        svg = draw(self.tmp, "turned", road + [(7.0, 100.0, "crossing", ""), (0.0, 100.0, "lane_change", "")])

        def screen_y(kind):
            group = re.search(r'<g id="warnings_%s_1">(.*?)</g>' % kind, svg, flags=re.S).group(1)
            return float(re.search(r'<use [^>]*\by="([-0-9.]+)"', group).group(1))
        self.assertGreater(screen_y("crossing"), screen_y("lane_change"))  # SVG's y grows downwards

    def test_a_square_network_is_one_panel_at_equal_scales(self):
        pts = [(random.uniform(0, 300), random.uniform(0, 300), "crossing", "") for _ in range(50)]
        svg = draw(self.tmp, "square", pts)
        self.assertEqual(markers(svg), len(pts))
        self.assertNotIn("segments", svg)


if __name__ == "__main__":
    unittest.main()
