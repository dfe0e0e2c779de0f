#!/usr/bin/python3
"""batch/plots.py: the figures' titles, labels, n and split by the swept parameter; Wilson
intervals against known values; the paired differences against an independent computation;
report.md's header. Run by ctest (label batch) with STSIM_BINARY and STSIM_SOURCE_DIR set; exits
77 (skipped) without matplotlib, SUMO or the binary."""
import csv
import importlib.util
import math
import os
import shutil
import struct
import subprocess
import sys
import tempfile
import unittest

SRC = os.environ.get("STSIM_SOURCE_DIR", os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", ".."))
BINARY = os.environ.get("STSIM_BINARY", "")

try:
    import matplotlib  # noqa: F401
except ImportError:
    print("python3-matplotlib not installed: skipped")
    sys.exit(77)

spec = importlib.util.spec_from_file_location("plots", os.path.join(SRC, "batch", "plots.py"))
plots = importlib.util.module_from_spec(spec)
spec.loader.exec_module(plots)
from matplotlib.container import ErrorbarContainer  # noqa: E402

# t_{0.975, dof} from the standard tables, written out here rather than taken from stats.cpp
T975 = {1: 12.706205, 2: 4.302653, 3: 3.182446, 4: 2.776445}


def rows_of(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def texts(fig):
    """Every title, suptitle, axis label, tick label and legend text of a figure."""
    out = [fig._suptitle.get_text()] if fig._suptitle else []
    for ax in fig.axes:
        out += [ax.get_title(), ax.get_xlabel(), ax.get_ylabel()]
        out += [t.get_text() for t in ax.get_xticklabels() + ax.get_yticklabels()]
        if ax.get_legend():
            out += [t.get_text() for t in ax.get_legend().get_texts()]
    return out


class Intervals(unittest.TestCase):
    def test_wilson_matches_published_values(self):
        # Wilson score 95 % intervals (z = 1.96): 0/10 -> [0, z²/(n+z²)], 5/10 -> [0.2366, 0.7634],
        # 10/10 -> [n/(n+z²), 1], 1/20 -> [0.0089, 0.2361]
        z2 = 1.959963984540054 ** 2
        self.assertEqual(plots.wilson(0, 10)[0], 0.0)
        self.assertAlmostEqual(plots.wilson(0, 10)[1], z2 / (10 + z2), places=12)
        self.assertAlmostEqual(plots.wilson(0, 10)[1], 0.2775, places=4)
        lo, hi = plots.wilson(5, 10)
        self.assertAlmostEqual(lo, 0.2366, places=4)
        self.assertAlmostEqual(hi, 0.7634, places=4)
        self.assertAlmostEqual(plots.wilson(10, 10)[0], 10 / (10 + z2), places=12)
        self.assertEqual(plots.wilson(10, 10)[1], 1.0)
        lo, hi = plots.wilson(1, 20)
        self.assertAlmostEqual(lo, 0.0089, places=4)
        self.assertAlmostEqual(hi, 0.2361, places=4)
        self.assertIsNone(plots.wilson(0, 0))
        self.assertEqual(plots.share_text(5, 10), "0.500 (95 % CI 0.237–0.763, 5/10)")

    def test_labels_and_precision(self):
        self.assertEqual(plots.label("sumo_collisions"), "SUMO collisions per run")
        self.assertEqual(plots.label("warnings.per_vehicle_km"), "warnings per vehicle-km")
        self.assertEqual(plots.label("warnings.per_vehicle_km_by_type.rear_end"), "rear end warnings per vehicle-km")
        self.assertEqual(plots.label("min_ttc"), "minimum TTC per warning episode (s)")
        # 3 significant digits on the column's largest value, the same decimals for every cell
        d = plots.decimals([58.6, 42.9, -15.7])
        self.assertEqual(d, 1)
        self.assertEqual(plots.estimate(58.6, 10.9, 20, d), "58.6 ± 10.9 (95 % CI, n=20)")
        self.assertEqual(plots.estimate(1.429, 0.09129, 20, plots.decimals([1.169, 1.429])),
                         "1.43 ± 0.09 (95 % CI, n=20)")
        self.assertEqual(plots.estimate(0.26, None, 1, 3), "0.260 (n=1, no interval)")


@unittest.skipUnless(BINARY and os.path.exists(BINARY) and shutil.which("sumo"), "needs the stsim binary and SUMO")
class IncidentBatch(unittest.TestCase):
    """A short incident study (the brake action against none, 3 paired seeds, 150 s: the first
    incident at 120 s) run by the real batch, its report and figures read back."""

    @classmethod
    def setUpClass(cls):
        cls.dir = tempfile.mkdtemp(prefix="stsim_plots_test_")
        exp = os.path.join(cls.dir, "exp.yaml")
        with open(exp, "w") as f:
            f.write("name: plots_test\ncommand: highway\nbase: %s/networks/motorway/incident.yaml\n"
                    "sweep:\n  action: [none, brake]\nfixed:\n  end: 150\n  detector: five\n"
                    "  collision_action: warn\nseeds: 3\n" % os.path.abspath(SRC))
        cls.out = os.path.join(cls.dir, "out")
        subprocess.run([BINARY, "batch", exp, "--out", cls.out, "--jobs", "2"], check=True, cwd=cls.dir,
                       stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
        cls.b = plots.Batch(cls.out)
        with open(os.path.join(cls.out, "report.md")) as f:
            cls.report = f.read()

    @classmethod
    def tearDownClass(cls):
        shutil.rmtree(cls.dir, ignore_errors=True)

    def test_report_header_states_what_was_run(self):
        for line in ["# Batch report: plots_test\n",
                     "| scenario (base) | networks/motorway/incident.yaml (motorway merge with four hard-braking "
                     "incidents downstream) |\n",
                     "| command | highway |\n", "| detector | five |\n", "| prediction | road |\n",
                     "| run length | 150 s simulated, 1500 steps of 0.1 s |\n",
                     "| seeds | 3 per combination (seed: 1..3), the same for every combination |\n",
                     "| swept | action: none, brake |\n", "| runs | 6 (6 done, 0 not done) |\n"]:
            self.assertIn(line, self.report)
        self.assertIn("(paired_differences.png)", self.report)

    def independent_differences(self, metric):
        runs = rows_of(os.path.join(self.out, "runs.csv"))
        by = {(r["action"], r["seed"]): float(r[metric]) for r in runs}
        diffs = [by[("brake", s)] - by[("none", s)] for s in ("1", "2", "3")]
        mean = sum(diffs) / len(diffs)
        sd = math.sqrt(sum((d - mean) ** 2 for d in diffs) / (len(diffs) - 1))
        return diffs, mean, T975[len(diffs) - 1] * sd / math.sqrt(len(diffs))

    def test_paired_difference_matches_an_independent_computation(self):
        # collisions are contacts (the bodies touch), what the report shows
        diffs, mean, half = self.independent_differences("contacts")
        paired = rows_of(os.path.join(self.out, "paired.csv"))
        self.assertEqual(len(paired), 1)
        self.assertAlmostEqual(float(paired[0]["contacts.diff_mean"]), mean, places=9)
        self.assertAlmostEqual(float(paired[0]["contacts.diff_ci95"]), half, delta=1e-5 * max(1.0, half))
        d = plots.decimals([mean])
        self.assertIn(" | %.*f ± %.*f (95 %% CI, n=3) |" % (d, mean, d, half), self.report)
        fig = plots.paired_figure(self.b, ["contacts"])
        ax = fig.axes[0]
        # a row per comparison: the differences run along x
        self.assertEqual(sorted(ax.lines[0].get_xdata()), sorted(diffs))  # the seeds' dots
        bars = [c for c in ax.containers if isinstance(c, ErrorbarContainer)]
        self.assertEqual(len(bars), 1)
        self.assertAlmostEqual(bars[0].lines[0].get_xdata()[0], mean, places=9)
        (seg,) = bars[0].lines[2][0].get_segments()
        self.assertAlmostEqual(seg[0][0], mean - half, delta=1e-5 * max(1.0, half))
        self.assertAlmostEqual(seg[1][0], mean + half, delta=1e-5 * max(1.0, half))
        t = texts(fig)
        self.assertIn("collisions (bodies touching) (n=3 pairs)", t)
        self.assertIn("difference in collisions (bodies touching) per run", t)
        self.assertIn("brake − none", t)
        self.assertTrue(fig._suptitle.get_text())

    def test_min_ttc_split_by_type_from_conflicts_only(self):
        fig = plots.min_ttc_figure(self.b)
        if fig is None:
            self.assertFalse(any(plots.min_ttc_values(self.b).values()))
            return
        # counted independently: each run's conflicts.csv rows of SSAM's types, by action and type
        zero, positive = {}, {}
        for r in rows_of(os.path.join(self.out, "runs.csv")):
            for c in rows_of(os.path.join(self.out, "runs", r["run_id"], "conflicts.csv")):
                if c["type"] not in ("rear_end", "lane_change", "crossing"):
                    continue
                v = float(c["min_ttc"])
                k = (r["action"], c["type"])
                (zero if v == 0 else positive)[k] = (zero if v == 0 else positive).get(k, 0) + 1
        types = [t for t in ("rear_end", "lane_change", "crossing")
                 if any(k[1] == t for k in list(zero) + list(positive))]
        self.assertEqual([ax.get_title() for ax in fig.axes], ["%s conflicts" % t.replace("_", "-") for t in types])
        for ax, t in zip(fig.axes, types):
            legend = [x.get_text() for x in ax.get_legend().get_texts()]
            self.assertEqual(legend, ["action=%s: n=%d (TTC 0: %d)" % (a, positive.get((a, t), 0), zero.get((a, t), 0))
                                      for a in ("none", "brake")])
        text = " ".join(texts(fig))
        self.assertNotIn("lane marker", text)
        self.assertNotIn("curb", text)
        self.assertEqual(fig.axes[0].get_xlabel(), "minimum TTC per conflict (s)")
        self.assertTrue(fig.axes[0].get_ylabel().startswith("conflicts per "))

    def test_collisions_labelled_and_split(self):
        fig = plots.collisions_figure(self.b)
        ax = fig.axes[0]
        self.assertEqual(ax.get_ylabel(), "collisions (bodies touching) per run")
        self.assertEqual(ax.get_xlabel(), "action")
        self.assertEqual([t.get_text() for t in ax.get_xticklabels()], ["none", "brake"])
        self.assertIn("n=3 seeds", ax.get_title())
        self.assertNotIn("contacts", " ".join(texts(fig)))
        self.assertNotIn("all", [t.get_text() for t in ax.get_xticklabels()])

    def test_hindsight_shares_carry_wilson_intervals_and_n(self):
        kinds, rows = plots.hindsight_rows(self.out)
        fig = plots.hindsight_figure(self.b, kinds, rows)
        recall = next(ax for ax in fig.axes if ax.get_title() == "collision recall")
        drawn = 0  # the rows with a share draw an interval, in order
        for r in rows:
            k, n = int(r["collisions_warned"]), int(r["collisions"])
            if n == 0:  # no contact in the combination: nothing to share
                self.assertIn("n/a (n=0)", [t.get_text() for t in recall.texts])
                continue
            self.assertIn("%d/%d" % (k, n), [t.get_text() for t in recall.texts])
            lo, hi = plots.wilson(k, n)
            bars = [c for c in recall.containers if isinstance(c, ErrorbarContainer)]
            (seg,) = bars[drawn].lines[2][0].get_segments()
            drawn += 1
            self.assertAlmostEqual(seg[0][0], lo, places=12)
            self.assertAlmostEqual(seg[1][0], hi, places=12)
            self.assertIn(plots.share_text(k, n), self.report)
        self.assertIn("share (Wilson 95 % CI)", texts(fig))
        self.assertTrue(fig._suptitle.get_text())

    def test_every_png_in_the_report_exists(self):
        for name in ("min_ttc_distribution.png", "collisions_by_action.png", "paired_differences.png", "hindsight.png"):
            with open(os.path.join(self.out, name), "rb") as f:
                self.assertEqual(f.read(4), b"\x89PNG")
            self.assertIn("(%s)" % name, self.report)


@unittest.skipUnless(BINARY and os.path.exists(BINARY), "needs the stsim binary")
class ManyCombinations(unittest.TestCase):
    """A made-up highway study of 15 combinations (5 demand scales x 3 detectors, 3 seeds, a 60 s
    warm-up): the runs' files written here, the tables and the report by `stsim batch merge`. The
    report's headline and paired differences by type against a computation of this test's own; the
    PNGs at most 2400 px wide; the warm-up honoured in the figures as in the tables."""

    SCALES = ["0.5", "0.75", "1.0", "1.25", "1.5"]
    DETECTORS = ["concentric", "five", "box"]

    @classmethod
    def conflicts(cls, scale, detector, seed):
        """(type, begin, min_ttc) rows of a run: deterministic, more with demand; one before the warm-up."""
        n = int(3 * float(scale) + seed + cls.DETECTORS.index(detector))
        rows = [("rear_end", 30.0, 0.05)]  # the warm-up's
        for i in range(n):
            rows.append((["rear_end", "rear_end", "lane_change", "crossing"][i % 4], 60.0 + 10 * i,
                         0.3 + ((i * 7 + seed * 3) % 11) / 10.0))
        return rows

    @classmethod
    def setUpClass(cls):
        cls.dir = tempfile.mkdtemp(prefix="stsim_plots_many_")
        exp = os.path.join(cls.dir, "exp.yaml")
        with open(exp, "w") as f:
            f.write("name: many\ncommand: highway\nbase: %s/networks/motorway/scenario.yaml\n"
                    "sweep:\n  demand_scale: [%s]\n  detector: [%s]\nseeds: 3\nwarmup: 60\n"
                    % (os.path.abspath(SRC), ", ".join(cls.SCALES), ", ".join(cls.DETECTORS)))
        listing = subprocess.run([BINARY, "batch", exp, "--list"], check=True, cwd=cls.dir, capture_output=True,
                                 text=True).stdout
        shard = os.path.join(cls.dir, "shard")
        os.makedirs(os.path.join(shard, "runs"))
        shutil.copyfile(exp, os.path.join(shard, "experiment.yaml"))
        cls.rates = {}  # (scale, detector, seed) -> rear-end conflicts per vehicle-km after the warm-up
        for line in listing.splitlines():
            parts = line.split()
            run_id, params = parts[1], dict(p.split("=", 1) for p in parts[2:])
            scale, detector, seed = params["demand_scale"], params["detector"], int(params["seed"])
            d = os.path.join(shard, "runs", run_id)
            os.makedirs(d)
            with open(os.path.join(d, "result.yaml"), "w") as f:
                f.write("status: done\nerror: \"\"\nwall_seconds: 1\n")
            km = 20.0 * float(scale) + seed
            with open(os.path.join(d, "summary.json"), "w") as f:
                f.write('{"vehicle_km": %r, "vehicles": 400, "simulated_s": 420, "contacts": %d}\n' % (km, seed % 2))
            with open(os.path.join(d, "exposure.csv"), "w") as f:
                f.write("time,vehicle_km,vehicles\n0,0,0\n59.9,%r,90\n60,%r,100\n420,%r,400\n" % (km / 8, km / 7, km))
            rows = cls.conflicts(scale, detector, seed)
            with open(os.path.join(d, "conflicts.csv"), "w") as f:
                f.write("first,second,type,begin,min_ttc\n")
                for i, (t, begin, ttc) in enumerate(rows):
                    f.write("a%d,b%d,%s,%r,%r\n" % (i, i, t, begin, ttc))
            after = [r for r in rows if r[1] >= 60.0]
            cls.rates[(scale, detector, seed)] = sum(1 for r in after if r[0] == "rear_end") / (km - km / 7)
        cls.out = os.path.join(cls.dir, "out")
        subprocess.run([BINARY, "batch", "merge", shard, "--out", cls.out], check=True, cwd=cls.dir,
                       stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
        cls.b = plots.Batch(cls.out)
        with open(os.path.join(cls.out, "report.md")) as f:
            cls.report = f.read()

    @classmethod
    def tearDownClass(cls):
        shutil.rmtree(cls.dir, ignore_errors=True)

    def test_every_png_at_most_2400_px_wide(self):
        pngs = [n for n in os.listdir(self.out) if n.endswith(".png")]
        self.assertIn("paired_differences.png", pngs)
        self.assertIn("min_ttc_distribution.png", pngs)
        for name in pngs:
            with open(os.path.join(self.out, name), "rb") as f:
                head = f.read(24)
            self.assertEqual(head[:8], b"\x89PNG\r\n\x1a\n")
            width, height = struct.unpack(">II", head[16:24])  # the IHDR chunk
            self.assertLessEqual(width, 2400, name)
            self.assertGreater(height, 0)

    def test_headline_is_rear_end_per_vehicle_km_with_paired_intervals(self):
        self.assertIn("## Headline: conflicts per vehicle-km by type (`report.headline: conflicts_per_vehicle_km`)",
                      self.report)
        self.assertIn("the first 60 s of every run (the warm-up) left out", self.report)
        # demand 1.5 against 0.5, detector box: the seed-by-seed differences computed here
        diffs = [self.rates[("1.5", "box", s)] - self.rates[("0.5", "box", s)] for s in (1, 2, 3)]
        mean = sum(diffs) / 3
        half = T975[2] * math.sqrt(sum((d - mean) ** 2 for d in diffs) / 2) / math.sqrt(3)
        paired = rows_of(os.path.join(self.out, "paired.csv"))
        row = next(r for r in paired if r["compared"] == "demand_scale" and r["demand_scale"] == "1.5"
                   and r["detector"] == "box")
        self.assertAlmostEqual(float(row["rate.per_vehicle_km.rear_end.diff_mean"]), mean, places=12)
        self.assertAlmostEqual(float(row["rate.per_vehicle_km.rear_end.diff_ci95"]), half, delta=1e-5 * max(half, 1))
        line = next(l for l in self.report.splitlines() if l.startswith("| demand_scale vs 0.5 | 1.5 | box | 3 |"))
        d = plots.decimals([float(r["rate.per_vehicle_km.rear_end.diff_mean"]) for r in paired])
        self.assertIn("| %.*f ± %.*f (95 %% CI, n=3) |" % (d, mean, d, half), line)

    def test_paired_figure_wraps_and_histograms_honour_the_warmup(self):
        fig = plots.paired_figure(self.b)
        visible = [ax for ax in fig.axes if ax.get_visible()]
        self.assertEqual(len(visible), 5)  # rear-end, lane change, crossing, all; collisions
        self.assertLessEqual(fig.get_size_inches()[0] * plots.DPI, 2400)
        # a row per comparison: 4 demand scales x 3 detectors, 2 detectors x 5 demand scales
        self.assertEqual(len(visible[0].get_yticklabels()), 4 * 3 + 2 * 5)
        by = plots.min_ttc_values(self.b)
        for (scale, detector), per in by.items():
            n = sum(len(v) for v in per.values())
            expected = sum(len([r for r in self.conflicts(scale, detector, s) if r[1] >= 60]) for s in (1, 2, 3))
            self.assertEqual(n, expected)
            self.assertNotIn(0.05, per["rear_end"])  # the warm-up's conflict


if __name__ == "__main__":
    unittest.main()
