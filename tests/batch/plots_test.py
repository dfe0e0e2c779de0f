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
        self.assertEqual(sorted(ax.lines[0].get_ydata()), sorted(diffs))  # the seeds' dots
        bars = [c for c in ax.containers if isinstance(c, ErrorbarContainer)]
        self.assertEqual(len(bars), 1)
        self.assertAlmostEqual(bars[0].lines[0].get_ydata()[0], mean, places=9)
        (seg,) = bars[0].lines[2][0].get_segments()
        self.assertAlmostEqual(seg[0][1], mean - half, delta=1e-5 * max(1.0, half))
        self.assertAlmostEqual(seg[1][1], mean + half, delta=1e-5 * max(1.0, half))
        t = texts(fig)
        self.assertIn("collisions (bodies touching) (n=3 pairs)", t)
        self.assertIn("difference in collisions (bodies touching) per run", t)
        self.assertIn("brake − none", t)
        self.assertTrue(fig._suptitle.get_text())

    def test_min_ttc_split_by_action_and_ttc_zero_apart(self):
        fig = plots.min_ttc_figure(self.b)
        zero = {"none": 0, "brake": 0}
        positive = {"none": 0, "brake": 0}
        for r in rows_of(os.path.join(self.out, "runs.csv")):
            for w in rows_of(os.path.join(self.out, "runs", r["run_id"], "warnings.csv")):
                v = float(w["min_ttc"])
                if math.isfinite(v):
                    (zero if v == 0 else positive)[r["action"]] += 1
        legend = [t.get_text() for t in fig.axes[0].get_legend().get_texts()]
        self.assertEqual(legend, ["action=%s: n=%d (TTC 0, left out: %d)" % (a, positive[a], zero[a])
                                  for a in ("none", "brake")])
        self.assertFalse(any("all" in t for t in legend))
        self.assertIn("%d at TTC 0" % (zero["none"] + zero["brake"]), fig._suptitle.get_text())
        self.assertEqual(fig.axes[0].get_xlabel(), "minimum TTC per episode (s)")
        self.assertTrue(fig.axes[0].get_ylabel().startswith("episodes per "))
        # no bar from 0: the first bin starts at 0 but holds only TTC > 0
        self.assertGreater(sum(positive.values()), 0)

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


if __name__ == "__main__":
    unittest.main()
