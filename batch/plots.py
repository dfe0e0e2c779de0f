#!/usr/bin/python3
"""Plots and report.md for a `stsim batch` output folder (runs.csv, summary.csv, paired.csv,
hindsight.csv, runs/*/warnings.csv).

Uses Debian's python3-matplotlib. Called by `stsim batch`; can be re-run by hand:
    /usr/bin/python3 batch/plots.py OUT_DIR

Every figure is built by a function that returns the matplotlib Figure (none of them saves), so a
test can read its titles, labels and legends: metric_figure, min_ttc_figure, collisions_figure,
paired_figure, hindsight_figure; load(out) reads the folder they all take.
"""
import csv
import importlib.util
import json
import math
import os
import re
import shutil
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

Z95 = 1.959963984540054  # the normal 0.975 quantile (Wilson intervals)
DPI = 120
MAX_WIDTH_PX = 2400  # every figure: wider ones wrap their panels into rows instead
TYPES = ["rear_end", "lane_change", "crossing", "pedestrian"]  # SSAM's conflict types and a person's
# report.headline -> the rate family of the runs' metrics (batch/src/rates.cpp)
HEADLINES = {"conflicts_per_vehicle_km": "per_vehicle_km", "conflicts_per_hour": "per_hour",
             "conflicts_per_entering_vehicle": "per_entering_vehicle"}

# metric key -> (what it counts, unit): "SUMO collisions" + "per run" reads "SUMO collisions per run"
LABELS = {
    "sumo_collisions": ("SUMO collisions", "per run"),
    "contacts": ("collisions (bodies touching)", "per run"),
    "mingap_violations": ("SUMO minGap violations (bodies apart)", "per run"),
    "sumo_collision_steps": ("SUMO collision reports (steps touching)", "per run"),
    "collisions_warned": ("collisions the collider warned of", "per run"),
    "warnings.total": ("warnings", "per run"),
    "warnings.conflicts": ("conflict warnings (per ego)", "per run"),
    "conflicts.count": ("conflicts (one per pair and encounter)", "per run"),
    "conflicts.per_vehicle_km": ("conflicts", "per vehicle-km"),
    "conflicts.tet_s": ("time exposed below TTC*", "s per run"),
    "conflicts.tit_s2": ("time-integrated TTC below TTC*", "s² per run"),
    "warnings.per_vehicle_km": ("warnings", "per vehicle-km"),
    "vehicle_km": ("distance driven", "vehicle-km per run"),
    "exposure.vehicle_km": ("distance driven after the warm-up", "vehicle-km per run"),
    "exposure.hours": ("time simulated after the warm-up", "h per run"),
    "exposure.entering_vehicles": ("vehicles entering after the warm-up", "per run"),
    "after_warmup.collisions.events": ("collisions (contacts) after the warm-up", "per run"),
    "vehicles": ("vehicles", "per run"),
    "collision_checks": ("collision checks", "per run"),
    "min_ttc": ("minimum TTC per warning episode", "s"),
    "near_miss_recall": ("near-miss recall", "share"),
    "confirmed_share": ("confirmed share", "share"),
}
# patterns for the families of keys: (regex, what, unit), \1 the kind, zone or type
LABEL_PATTERNS = [
    (r"^rate\.per_vehicle_km\.all$", "conflicts (all types)", "per vehicle-km"),
    (r"^rate\.per_hour\.all$", "conflicts (all types)", "per hour"),
    (r"^rate\.per_entering_vehicle\.all$", "conflicts (all types)", "per entering vehicle"),
    (r"^rate\.per_vehicle_km\.with_bicycle\.all$", "conflicts with a bicycle (all types)", "per vehicle-km"),
    (r"^rate\.per_hour\.with_bicycle\.all$", "conflicts with a bicycle (all types)", "per hour"),
    (r"^rate\.per_entering_vehicle\.with_bicycle\.all$", "conflicts with a bicycle (all types)", "per entering vehicle"),
    (r"^rate\.per_vehicle_km\.with_bicycle\.(\w+)$", r"\1 conflicts with a bicycle", "per vehicle-km"),
    (r"^rate\.per_hour\.with_bicycle\.(\w+)$", r"\1 conflicts with a bicycle", "per hour"),
    (r"^rate\.per_entering_vehicle\.with_bicycle\.(\w+)$", r"\1 conflicts with a bicycle", "per entering vehicle"),
    (r"^counted\.with_bicycle\.all$", "conflicts with a bicycle after the warm-up (all types)", "per run"),
    (r"^counted\.with_bicycle\.(\w+)$", r"\1 conflicts with a bicycle after the warm-up", "per run"),
    (r"^conflicts\.with_bicycle\.count$", "conflicts with a bicycle", "per run"),
    (r"^conflicts\.with_bicycle\.between_bicycles$", "conflicts between two bicycles", "per run"),
    (r"^conflicts\.with_bicycle\.by_type\.(\w+)$", r"\1 conflicts with a bicycle", "per run"),
    (r"^rate\.per_vehicle_km\.(\w+)$", r"\1 conflicts", "per vehicle-km"),
    (r"^rate\.per_hour\.(\w+)$", r"\1 conflicts", "per hour"),
    (r"^rate\.per_entering_vehicle\.(\w+)$", r"\1 conflicts", "per entering vehicle"),
    (r"^counted\.all$", "conflicts after the warm-up (all types)", "per run"),
    (r"^counted\.(\w+)$", r"\1 conflicts after the warm-up", "per run"),
    (r"^conflicts\.per_vehicle_km_by_type\.(\w+)$", r"\1 conflicts", "per vehicle-km"),
    (r"^conflicts\.by_type\.(\w+)$", r"\1 conflicts", "per run"),
    (r"^warnings\.per_vehicle_km_by_(?:type|kind)\.(\w+)$", r"\1 warnings", "per vehicle-km"),
    (r"^warnings\.by_(?:type|kind|zone)\.(\w+)$", r"\1 warnings", "per run"),
    (r"^tet_s\.(\w+)$", r"time exposed below the safe time, \1", "s per run"),
    (r"^tit_s2\.(\w+)$", r"time-integrated TTC deficit, \1", "s² per run"),
]


def quantity(key):
    """(what, unit) of a metric key: the table, the patterns, else the key itself, unitless."""
    if key in LABELS:
        return LABELS[key]
    for pattern, what, unit in LABEL_PATTERNS:
        if re.match(pattern, key):
            return re.sub(pattern, what, key).replace("_", " "), unit
    return key.replace("_", " "), ""


def label(key):
    """A metric key as an analyst reads it: sumo_collisions -> "SUMO collisions per run"."""
    what, unit = quantity(key)
    if not unit:
        return what
    return "%s %s" % (what, unit) if unit.startswith("per ") else "%s (%s)" % (what, unit)


def wilson(k, n, z=Z95):
    """Wilson score interval (lo, hi) of the share k/n; None for n = 0."""
    if not n:
        return None
    p = k / n
    centre = (p + z * z / (2 * n)) / (1 + z * z / n)
    half = z * math.sqrt(p * (1 - p) / n + z * z / (4 * n * n)) / (1 + z * z / n)
    # the ends exact where the share is: 0/n reaches down to 0, n/n up to 1
    return (0.0 if k == 0 else max(0.0, centre - half)), (1.0 if k == n else min(1.0, centre + half))


def decimals(values, sig=3):
    """Decimals that give the largest of values `sig` significant digits: one precision a column."""
    vals = [abs(v) for v in values if v is not None and math.isfinite(v) and v != 0]
    if not vals:
        return 0
    return max(0, sig - 1 - int(math.floor(math.log10(max(vals)))))


def estimate(mean, half, n, d):
    """'estimate ± half-width (95 % CI, n=…)' at d decimals; no interval from fewer than 2."""
    if mean is None:
        return "n/a"
    if half is None or n is None or n < 2:
        return "%.*f (n=%s, no interval)" % (d, mean, n if n is not None else "?")
    return "%.*f ± %.*f (95 %% CI, n=%d)" % (d, mean, d, half, n)


def share_text(k, n):
    """A share with its Wilson interval and counts: '0.584 (95 % CI 0.579–0.589, 19458/33343)'."""
    ci = wilson(k, n)
    if ci is None:
        return "n/a"
    return "%.3f (95 %% CI %.3f–%.3f, %d/%d)" % (k / n, ci[0], ci[1], k, n)


def read_csv(path):
    with open(path, newline="") as f:
        rows = list(csv.reader(f))
    return rows[0], [dict(zip(rows[0], r)) for r in rows[1:]]


def num(s):
    try:
        v = float(s)
        return v if math.isfinite(v) else None
    except (TypeError, ValueError):
        return None


def fmt(v):
    x = num(v)
    return "" if x is None else "%.4g" % x


def find_col(cols, *patterns):
    for p in patterns:
        for c in cols:
            if re.search(p, c):
                return c
    return None


def conflict_maps(out, runs, sweep, warmup=0.0):
    """One conflict map per parameter combination, all seeds together (highway runs with a
    conflicts.csv: one point per conflict, no warnings); the network from the runs' summary.json,
    TTC* from it too (the map's title)."""
    # installed, both scripts sit in share/stsim; in the source tree the map's is the model's
    here = os.path.dirname(os.path.abspath(__file__))
    script = next((p for p in (os.path.join(here, "conflict_map.py"),
                               os.path.join(here, "..", "models", "highway", "conflict_map.py"))
                   if os.path.exists(p)), None)
    if script is None:
        return []
    groups = {}
    for r in runs:
        if r["status"] != "done":
            continue
        d = os.path.join(out, "runs", r["run_id"])
        path = os.path.join(d, "conflicts.csv")
        if not os.path.exists(path):
            continue
        with open(path, newline="") as f:
            header = next(csv.reader(f), [])
        if "conflict_x" not in header or "type" not in header:
            continue
        groups.setdefault(tuple(r[p] for p in sweep), []).append(d)
    if not groups:
        return []
    spec = importlib.util.spec_from_file_location("conflict_map", script)
    cm = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(cm)
    maps = []
    for key, dirs in sorted(groups.items()):
        label = ", ".join("%s=%s" % (p, v) for p, v in zip(sweep, key)) or "all runs"
        name = "conflict_map_" + (re.sub(r"[^A-Za-z0-9.]+", "_", "_".join(key)) if key else "all")
        net = None
        try:
            with open(os.path.join(dirs[0], "summary.json")) as f:
                net = json.load(f).get("net")
        except (OSError, ValueError):
            pass
        args = ["--out", os.path.join(out, name), "--title", "%s (%d runs)" % (label, len(dirs))]
        if net and os.path.exists(net):
            args += ["--net", net]
        files = [os.path.join(d, "conflicts.csv") for d in dirs]
        if warmup > 0:  # the maps show what the tables count: conflicts begun after the warm-up
            kept = []
            for path in files:
                header, rows = read_csv(path)
                # beside its run's summary.json, where the map reads TTC*
                folder = os.path.join(out, "after_warmup", os.path.basename(os.path.dirname(path)))
                os.makedirs(folder, exist_ok=True)
                if os.path.exists(os.path.join(os.path.dirname(path), "summary.json")):
                    shutil.copyfile(os.path.join(os.path.dirname(path), "summary.json"), os.path.join(folder, "summary.json"))
                dst = os.path.join(folder, "conflicts.csv")
                with open(dst, "w", newline="") as g:
                    w = csv.DictWriter(g, fieldnames=header)
                    w.writeheader()
                    w.writerows(r for r in rows if (num(r.get("begin")) or -1) >= warmup)
                kept.append(dst)
            files = kept
        if cm.main(args + files) != 0:
            continue
        maps.append((name, label))
    return maps


class Batch:
    """A batch output folder read once: runs, summary, paired differences, the experiment record."""

    def __init__(self, out):
        self.out = out
        self.runs_header, self.runs = read_csv(os.path.join(out, "runs.csv"))
        sum_header, self.summary = read_csv(os.path.join(out, "summary.csv"))
        # parameters sit between "status" and "wall_seconds"; the last of them is the seed key
        params = self.runs_header[self.runs_header.index("status") + 1: self.runs_header.index("wall_seconds")]
        self.sweep, self.seed_key = params[:-1], params[-1]
        self.metrics = [c[: -len(".mean")] for c in sum_header if c.endswith(".mean")]
        self.done = [r for r in self.runs if r["status"] == "done"]
        # each swept key's values in the experiment's order (the runs' order)
        self.values = {p: list(dict.fromkeys(r[p] for r in self.runs)) for p in self.sweep}
        self.seeds = list(dict.fromkeys(r[self.seed_key] for r in self.runs))
        path = os.path.join(out, "paired.csv")
        self.paired = read_csv(path)[1] if os.path.exists(path) else []
        self.record = read_record(os.path.join(out, "experiment.yaml"))
        self.warmup = num(self.record.get("warmup")) or 0.0
        report = self.record.get("report") or {}
        if isinstance(report, str):  # the record read without PyYAML: "{headline: X}"
            m = re.search(r"headline:\s*(\w+)", report)
            report = {"headline": m.group(1)} if m else {}
        self.headline_name = report.get("headline", "conflicts_per_vehicle_km")
        family = HEADLINES.get(self.headline_name, "per_vehicle_km")
        # the study's headline (highway runs with conflicts.csv): one rate by SSAM type, and all
        # types; the pedestrian's only where a run counted one (a motorway study has no persons), the
        # conflicts with a bicycle (all types) likewise; all types last, the headline
        def counted(t):
            return t not in ("pedestrian", "with_bicycle.all") or \
                any((num(r.get("counted.%s.mean" % t)) or 0) > 0 for r in self.summary)
        self.headline_types = ["rate.%s.%s" % (family, t) for t in TYPES + ["with_bicycle.all", "all"]
                               if "rate.%s.%s" % (family, t) in self.metrics and counted(t)]
        self.headline = find_col(self.metrics, r"per_vehicle_km.*total|total.*per_vehicle_km", r"per_vehicle_km",
                                 r"collision_checks$", r"warnings") or (self.metrics[0] if self.metrics else None)
        if self.headline_types:
            self.headline = self.headline_types[-1]
        # collisions are contacts (the bodies touch); SUMO's count holds its minGap violations too
        self.collisions = find_col(self.metrics, r"^contacts$", r"^sumo_collisions$", r"sumo.*collisions", r"collisions$")
        if self.warmup and "after_warmup.collisions.events" in self.metrics:  # what the tables count
            self.collisions = "after_warmup.collisions.events"

    def key(self, r):
        return tuple(r[p] for p in self.sweep)

    def combos(self):
        """The parameter combinations in the summary's order."""
        return [self.key(r) for r in self.summary]

    def combo_label(self, key, params=None):
        params = self.sweep if params is None else params
        return ", ".join("%s=%s" % (p, v) for p, v in zip(params, key)) or "all runs"

    def n(self, key, metric, params=None):
        """Done runs of a combination (of params, default the whole sweep) with a value of metric."""
        params = self.sweep if params is None else params
        return sum(1 for r in self.done if tuple(r[p] for p in params) == tuple(key) and num(r.get(metric)) is not None)

    def per_seed_differences(self, row, metric):
        """A paired.csv row's differences run by run, (seed, compared - baseline), from runs.csv."""
        axis = self.sweep.index(row["compared"])
        key = tuple(row[p] for p in self.sweep)
        base = key[:axis] + (row["baseline"],) + key[axis + 1:]
        by = {(self.key(r), r[self.seed_key]): num(r.get(metric)) for r in self.done}
        out = []
        for s in self.seeds:
            x, y = by.get((key, s)), by.get((base, s))
            if x is not None and y is not None:
                out.append((s, x - y))
        return out


def read_record(path):
    """experiment.yaml as written by the batch (a dict; empty if unreadable)."""
    try:
        import yaml
        with open(path) as f:
            return yaml.safe_load(f) or {}
    except ImportError:  # the record's top-level scalars only
        rec = {}
        with open(path) as f:
            for line in f:
                m = re.match(r"^(\w+): (.+)$", line.rstrip())
                if m:
                    rec[m.group(1)] = m.group(2)
        return rec
    except (OSError, ValueError):
        return {}


def _panels(n, width=6.0, height=4.0):
    """One axes, or a grid of small panels for many series (readable for a few or for dozens)."""
    if n <= 6:
        fig, ax = plt.subplots(figsize=(width, height))
        return fig, [ax] * max(1, n)
    cols = min(4, n)
    rows = (n + cols - 1) // cols
    fig, axes = plt.subplots(rows, cols, figsize=(3.2 * cols, 2.4 * rows + 0.8), sharex=True, squeeze=False)
    flat = [a for row in axes for a in row]
    for a in flat[n:]:
        a.set_visible(False)
    return fig, flat[:n]


def metric_figure(b, x):
    """The headline metric against a numeric swept parameter, one line per combination of the
    other swept parameters (mean and 95 % t-interval over seeds, from summary.csv)."""
    m = b.headline
    others = [p for p in b.sweep if p != x]
    groups = {}
    for r in b.summary:
        groups.setdefault(tuple(r[p] for p in others), []).append(r)
    fig, ax = plt.subplots(figsize=(6.4, 4.2))
    ns = set()
    for key, rows in groups.items():
        rows = sorted((r for r in rows if num(r.get(m + ".mean")) is not None), key=lambda r: num(r[x]))
        ns |= {b.n(b.key(r), m) for r in rows}
        ax.errorbar([num(r[x]) for r in rows], [num(r[m + ".mean"]) for r in rows],
                    yerr=[num(r.get(m + ".ci95")) or 0.0 for r in rows], marker="o", capsize=3,
                    label=b.combo_label(key, others))
    n_text = "n=%d seeds" % min(ns) if len(ns) == 1 else "n=%d-%d seeds" % (min(ns), max(ns)) if ns else "n=0"
    ax.set_title("%s against %s\n(mean ± 95 %% CI over seeds, %s per point)" % (label(m), x, n_text), fontsize=10)
    ax.set_xlabel(x)
    ax.set_ylabel(label(m))
    ax.grid(alpha=0.3)
    if others:
        ax.legend(fontsize=8)
    fig.tight_layout()
    return fig


def read_conflicts(path, warmup=0.0):
    """A run's conflicts.csv rows of SSAM's types whose encounter began at or after the warm-up
    (the batch's rule, batch/src/conflicts.cpp)."""
    if not os.path.exists(path):
        return None
    _, rows = read_csv(path)
    return [r for r in rows if r.get("type") in TYPES and (warmup <= 0 or (num(r.get("begin")) or -1) >= warmup)]


def min_ttc_values(b):
    """Per parameter combination and SSAM type, the minimum TTC of every conflict after the
    warm-up (runs' conflicts.csv, one row per conflict; the warnings and road warnings are not in it)."""
    by = {}
    for r in b.done:
        rows = read_conflicts(os.path.join(b.out, "runs", r["run_id"], "conflicts.csv"), b.warmup)
        if rows is None:
            continue
        per = by.setdefault(b.key(r), {t: [] for t in TYPES})
        for c in rows:
            v = num(c.get("min_ttc"))
            if v is not None:
                per[c["type"]].append(v)
    return by


def nice_step(span, bins=30):
    raw = span / bins
    mag = 10 ** math.floor(math.log10(raw))
    return next(s * mag for s in (1, 2, 2.5, 5, 10) if s * mag >= raw)


def min_ttc_figure(b, by=None):
    """Distribution of the conflicts' minimum TTC, one panel per SSAM type (columns); a line per
    parameter combination, or with more than 6 combinations one row of panels per combination.
    Conflicts at TTC 0 (the bodies touching) are left out of the bins and counted in the label."""
    by = min_ttc_values(b) if by is None else by
    if not any(v for per in by.values() for v in per.values()):
        return None
    keys = [k for k in b.combos() if k in by] + [k for k in by if k not in b.combos()]
    types = [t for t in TYPES if any(by[k][t] for k in keys)]
    positive = [v for k in keys for t in types for v in by[k][t] if v > 0]
    hi = max(positive) if positive else 1.0
    step = nice_step(hi)
    bins = [step * i for i in range(int(math.ceil(hi / step)) + 1)] or [0, step]
    if len(bins) < 2:
        bins.append(step)
    stacked = len(keys) > 6  # a row of panels per combination
    nrows = len(keys) if stacked else 1
    fig, axes = plt.subplots(nrows, len(types), squeeze=False, sharex=True, constrained_layout=True,
                             figsize=(min(MAX_WIDTH_PX / DPI, 4.4 * len(types)), (2.0 * nrows + 1.0) if stacked else 4.2))
    zero_total = total = 0
    for ti, t in enumerate(types):
        for ki, key in enumerate(keys):
            ax = axes[ki if stacked else 0][ti]
            vals = by[key][t]
            pos = [v for v in vals if v > 0]
            zero = len(vals) - len(pos)
            zero_total += zero
            total += len(vals)
            text = "%s: n=%d (TTC 0: %d)" % (b.combo_label(key), len(pos), zero)
            ax.hist(pos, bins=bins, histtype="step", linewidth=1.5, color="C%d" % (ki % 10), label=text)
            if stacked:
                ax.set_title("%s\n%s" % (t.replace("_", "-"), text), fontsize=7)
        for row in range(nrows):
            ax = axes[row][ti]
            if not stacked:
                ax.set_title("%s conflicts" % t.replace("_", "-"), fontsize=9)
                ax.legend(fontsize=7)
            if row == nrows - 1:
                ax.set_xlabel("minimum TTC per conflict (s)", fontsize=8)
            if ti == 0:
                ax.set_ylabel("conflicts per %g s bin" % step, fontsize=8)
            ax.grid(alpha=0.3)
            ax.tick_params(labelsize=7)
    warm = ", after a %g s warm-up" % b.warmup if b.warmup else ""
    fig.suptitle("Minimum TTC per conflict by SSAM type (conflicts.csv, all seeds per combination%s)\n"
                 "%d conflicts; %d at TTC 0 (bodies touching) left out of the bins" % (warm, total, zero_total),
                 fontsize=10)
    return fig


def collision_rows(b):
    """(other params' values, action, mean, ci95, n) for each combination with the collisions."""
    coll = b.collisions
    others = [p for p in b.sweep if p != "action"]
    actions = sorted(b.values.get("action", []), key=lambda a: (a != "none", b.values["action"].index(a)))
    groups = list(dict.fromkeys(tuple(r[p] for p in others) for r in b.summary))
    out = []
    for g in groups:
        for action in actions:
            row = next((r for r in b.summary if r["action"] == action and tuple(r[p] for p in others) == g), None)
            m = num(row.get(coll + ".mean")) if row else None
            if m is None:
                continue
            out.append((g, action, m, num(row.get(coll + ".ci95")), b.n(g + (action,), coll, others + ["action"])))
    return out


def collisions_figure(b):
    """Collisions (contacts: the bodies touch) per action (the brake action against none), per combination of the other
    swept parameters: mean and 95 % t-interval over seeds (summary.csv), each run as a dot."""
    coll = b.collisions
    if "action" not in b.sweep or not coll:
        return None
    others = [p for p in b.sweep if p != "action"]
    rows = collision_rows(b)
    if not rows:
        return None
    actions = list(dict.fromkeys(a for _, a, _, _, _ in rows))
    groups = list(dict.fromkeys(g for g, _, _, _, _ in rows))
    fig, ax = plt.subplots(figsize=(max(5.0, 1.6 * len(groups) + 2.5), 4.2))
    width = 0.8 / max(1, len(actions))
    ns = set()
    for ai, action in enumerate(actions):
        xs, ys, es = [], [], []
        for gi, g in enumerate(groups):
            row = next((r for r in rows if r[0] == g and r[1] == action), None)
            if row is None:
                continue
            x = gi + (ai - (len(actions) - 1) / 2) * width if others else ai
            xs.append(x)
            ys.append(row[2])
            es.append(row[3] or 0.0)
            ns.add(row[4])
            dots = [num(r[coll]) for r in b.done if r["action"] == action and
                    tuple(r[p] for p in others) == g and num(r[coll]) is not None]
            ax.plot([x] * len(dots), dots, "k.", alpha=0.35, label="one run (seed)" if not xs[1:] and ai == 0 else None)
        ax.bar(xs, ys, width=width * 0.9 if others else 0.6, yerr=es, capsize=4, label="%s: mean ± 95 %% CI" % action,
               color="#999999" if action == "none" else "#cc3333" if ai == 1 else "C%d" % ai, alpha=0.85)
    if others:
        ax.set_xticks(range(len(groups)))
        ax.set_xticklabels([b.combo_label(g, others) for g in groups], fontsize=8)
        ax.set_xlabel(", ".join(others))
    else:
        ax.set_xticks(range(len(actions)))
        ax.set_xticklabels(actions)
        ax.set_xlabel("action")
    n_text = "n=%d seeds" % min(ns) if len(ns) == 1 else "n=%d-%d seeds" % (min(ns), max(ns))
    ax.set_title("%s by action\n(mean ± 95 %% CI over seeds, %s each)" % (label(coll), n_text), fontsize=10)
    ax.set_ylabel(label(coll))
    ax.legend(fontsize=8)
    ax.grid(alpha=0.3, axis="y")
    fig.tight_layout()
    return fig


def paired_metrics(b):
    """The paired figure's metrics: the headline by type (highway studies), else the headline, and
    the collisions."""
    head = b.headline_types or [b.headline]
    return [m for m in head + [b.collisions, find_col(b.metrics, r"^collisions_warned$")] if m]


def paired_figure(b, metrics=None):
    """The paired study's result: a panel per metric, wrapped into rows of at most 3 panels so the
    figure stays within MAX_WIDTH_PX at any number of combinations; in each panel a row per
    compared combination (paired.csv, a swept value against the key's first value on the same
    seeds) with every seed's difference as a dot and their mean with its 95 % t-interval."""
    metrics = paired_metrics(b) if metrics is None else metrics
    rows = [r for r in b.paired if (num(r.get("pairs")) or 0) >= 2]
    metrics = [m for m in metrics if any(num(r.get(m + ".diff_mean")) is not None for r in rows)]
    if not rows or not metrics:
        return None
    ncols = min(3, len(metrics))
    nrows = (len(metrics) + ncols - 1) // ncols
    names = []
    for r in rows:
        others = [p for p in b.sweep if p != r["compared"]]
        names.append("%s − %s" % (r[r["compared"]], r["baseline"]) +
                     (" (%s)" % b.combo_label(tuple(r[p] for p in others), others) if others else ""))
    panel_h = 0.32 * len(rows) + 1.6
    fig, axes = plt.subplots(nrows, ncols, squeeze=False, sharey=True, constrained_layout=True,
                             figsize=(min(MAX_WIDTH_PX / DPI, 4.6 * ncols + 2.4), panel_h * nrows + 0.6))
    flat = [a for row in axes for a in row]
    for a in flat[len(metrics):]:
        a.set_visible(False)
    ys = list(range(len(rows)))
    for ax, m in zip(flat, metrics):
        ns = set()
        for i, r in enumerate(rows):
            diffs = [d for _, d in b.per_seed_differences(r, m)]
            jitter = [((j * 0.6180339887) % 1 - 0.5) * 0.3 for j in range(len(diffs))]
            ax.plot(diffs, [i + j for j in jitter], "o", color="#4477aa", alpha=0.45, markersize=3.5,
                    label="one seed's difference" if i == 0 else None)
            mean, half = num(r.get(m + ".diff_mean")), num(r.get(m + ".diff_ci95"))
            ns.add(len(diffs))
            if mean is not None:
                ax.errorbar([mean], [i], xerr=[half or 0.0], fmt="D", color="black", capsize=4, markersize=5,
                            label="mean ± 95 % CI (t)" if i == 0 else None)
        ax.axvline(0.0, color="#555555", linewidth=0.8, linestyle="--")
        ax.set_yticks(ys)
        ax.set_yticklabels(names, fontsize=7)
        ax.set_ylim(len(rows) - 0.5, -0.5)
        what, unit = quantity(m)
        ax.set_xlabel("difference in %s" % label(m), fontsize=8)
        n_text = "n=%d pairs" % min(ns) if len(ns) == 1 else "n=%d-%d pairs" % (min(ns), max(ns))
        ax.set_title("%s (%s)" % (what, n_text), fontsize=9)
        ax.grid(alpha=0.3, axis="x")
        ax.tick_params(axis="x", labelsize=7)
        if m == metrics[0]:
            ax.legend(fontsize=7)
    fig.suptitle("Paired differences (compared − baseline) on the same seeds: each seed, and the mean with its "
                 "95 % t-interval", fontsize=10)
    return fig


def hindsight_rows(out):
    path = os.path.join(out, "hindsight.csv")
    if not os.path.exists(path):
        return None, []
    header, rows = read_csv(path)
    kinds = [c[: -len(".confirmed_share")] for c in header if c.endswith(".confirmed_share")]
    return kinds, rows


def hindsight_shares(kinds):
    """(name, part column, whole column) of every share hindsight.csv gives."""
    shares = [(k.replace("_", " ") + " warnings confirmed", k + ".confirmed", k + ".judged") for k in kinds]
    shares.append(("near-miss recall", "near_misses_warned", "near_misses"))
    shares.append(("crossing recall", "crossings_warned", "crossings"))
    shares.append(("collision recall", "collisions_warned", "collisions"))
    return shares


def hindsight_figure(b, kinds, rows):
    """Per parameter combination (pooled over seeds, hindsight.csv): each kind's confirmed share and
    the recall of near misses, crossings and collisions, with Wilson 95 % intervals and k/n. A
    share of nothing is no bar, marked n/a: it is not 0; a share nothing ever had is no panel."""
    shares = [s for s in hindsight_shares(kinds)
              if any(num(r.get(s[2])) for r in rows)] or hindsight_shares(kinds)[-3:-2]
    labels = [b.combo_label(tuple(r[p] for p in b.sweep)) for r in rows]
    fig, axes = plt.subplots(1, len(shares), sharey=True, squeeze=False,
                             figsize=(2.7 * len(shares) + 2.4, 0.32 * len(rows) + 2.4))
    ys = list(range(len(rows)))
    for si, (ax, (name, part, whole)) in enumerate(zip(axes[0], shares)):
        for y, r in zip(ys, rows):
            k, n = num(r.get(part)), num(r.get(whole))
            ci = wilson(k or 0, n) if n else None
            if ci is None:
                ax.text(0.02, y, "n/a (n=0)", va="center", fontsize=6, color="#777777")
                continue
            p = k / n
            ax.barh(y, p, height=0.7, color="C%d" % si, alpha=0.8)
            ax.errorbar([p], [y], xerr=[[max(0.0, p - ci[0])], [max(0.0, ci[1] - p)]], fmt="none", ecolor="black", capsize=2)
            inside = ci[1] > 0.75  # no room right of the interval: the counts go inside the bar
            ax.text(0.03 if inside else ci[1] + 0.02, y, "%d/%d" % (k, n), va="center", fontsize=6,
                    color="white" if inside else "black", fontweight="bold" if inside else "normal")
        ax.set_xlim(0, 1.0)
        ax.set_title(name, fontsize=8)
        ax.set_xlabel("share (Wilson 95 % CI)", fontsize=7)
        ax.grid(alpha=0.3, axis="x")
        ax.tick_params(labelsize=7)
    axes[0][0].set_yticks(ys)
    axes[0][0].set_yticklabels(labels, fontsize=7)
    axes[0][0].set_ylabel(", ".join(b.sweep) or "runs", fontsize=7)
    axes[0][0].invert_yaxis()
    fig.suptitle("Hindsight: confirmed shares and recall, pooled over the seeds of each combination "
                 "(k/n beside each bar)", fontsize=9)
    fig.tight_layout()
    return fig


def write_misses(f, out, runs, sweep, samples=5, warmup=0.0):
    """report.md's missed events: per parameter combination, the near misses and unsignalled
    crossings (each run's events.csv, at or after the warm-up) that were not warned the lead time
    ahead, counted, and the first few of them to look at (late: warned, but less than the lead
    time ahead)."""
    groups = {}
    for r in runs:
        path = os.path.join(out, "runs", r["run_id"], "events.csv")
        if r["status"] != "done" or not os.path.exists(path):
            continue
        g = groups.setdefault(tuple(r[p] for p in sweep), {"events": 0, "missed": []})
        _, rows = read_csv(path)
        rows = [e for e in rows if warmup <= 0 or (num(e["time"]) or -1) >= warmup]
        g["events"] += len(rows)
        g["missed"] += [dict(e, run=r["run_id"]) for e in rows if e["warned"] != "1"]
    if not any(g["missed"] for g in groups.values()):
        return

    def cell(text):  # a marker's name joins its two lanes with "|"
        return text.replace("|", "\\|")
    f.write("## Missed events (from each run's events.csv)\n\n"
            "Near misses and unsignalled crossings%s not warned the lead time ahead, per combination, and "
            "the first %d of them: late (warned, but less than the lead time ahead) or not warned at all.\n\n"
            % (" after the %g s warm-up" % warmup if warmup > 0 else "", samples))
    f.write("| " + " | ".join(sweep + ["missed", "time (s)", "kind", "ego", "foe / line", "lane", "x, y (m)", "warned", "run"]) + " |\n")
    f.write("|" + "---|" * (len(sweep) + 9) + "\n")
    for key, g in groups.items():
        for i, e in enumerate(g["missed"][:samples]):
            lead = num(e["lead"])
            cells = list(key) if i == 0 else [""] * len(key)
            cells += ["%d of %d" % (len(g["missed"]), g["events"]) if i == 0 else "", fmt(num(e["time"])), e["kind"],
                      cell(e["ego"]), cell(e["foe"]), cell(e["lane"]), "%.1f, %.1f" % (num(e["x"]), num(e["y"])),
                      "not" if lead is None else "%.1f s ahead" % lead, e["run"]]
            f.write("| " + " | ".join(cells) + " |\n")
    f.write("\n")


def write_ssm(f, sweep, summary, metrics):
    """report.md's SSM validation (runs with validate_ssm): the box TTC's agreement with SUMO's SSM
    device and each detector's recall of SSM's conflicts below the safe time, n/a where the runs
    had none to recall."""
    detectors = [m[len("ssm."): -len(".recall")] for m in metrics
                 if m.startswith("ssm.") and m.endswith(".recall")]
    rows = [r for r in summary if any(num(r.get("ssm.%s.recall.mean" % d)) is not None or
                                      num(r.get("ssm.%s.recalled.mean" % d)) is not None for d in detectors)]
    if not detectors or not rows:
        return
    f.write("## SSM validation (runs with validate_ssm)\n\n"
            "The box detector's TTC within 0.02 s of SUMO's SSM device on following samples, and each "
            "detector's recall of the SSM conflicts below the safe time (recalled/conflicts, mean over "
            "seeds); n/a: no SSM conflict to recall.\n\n")
    cols = sweep + ["within 0.02 s"] + ["%s recall" % d.split(".")[-1] for d in detectors]
    f.write("| " + " | ".join(cols) + " |\n|" + "---|" * len(cols) + "\n")
    for r in rows:
        cells = [r[p] for p in sweep] + [fmt(r.get("ssm.following.within_fraction.mean")) or "n/a"]
        for d in detectors:
            v = num(r.get("ssm.%s.recall.mean" % d))
            cells.append("n/a" if v is None else "%.3f (%s/%s)" % (
                v, fmt(r.get("ssm.%s.recalled.mean" % d)), fmt(r.get("ssm.%s.ssm_conflicts_below_safe_time.mean" % d))))
        f.write("| " + " | ".join(cells) + " |\n")
    f.write("\n")


def seeds_text(seeds):
    """1..20 for a run of consecutive seeds, else the list."""
    ints = [int(s) for s in seeds if re.match(r"^-?\d+$", s)]
    if len(ints) == len(seeds) and len(ints) > 2 and ints == list(range(ints[0], ints[0] + len(ints))):
        return "%d..%d" % (ints[0], ints[-1])
    return ", ".join(seeds)


def source_path(path):
    """A path inside the source tree relative to it (as the READMEs name files), else as given."""
    root = os.path.normpath(os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
    p = os.path.normpath(str(path))
    return os.path.relpath(p, root) if p.startswith(root + os.sep) else p


def scenario_text(record):
    base = record.get("base")
    if isinstance(base, dict):
        return "; ".join("%s: %s" % (k, source_path(v["scenario"] if isinstance(v, dict) else v))
                         for k, v in base.items())
    if not base:
        return "n/a"
    text = source_path(base)
    try:
        with open(base) as f:
            m = re.search(r"^description:\s*(.+)$", f.read(), re.M)
        if m:
            text += " (%s)" % m.group(1).strip().strip("\"'")
    except OSError:
        pass
    return text


def run_facts(b):
    """What every run's summary.json says: detector, prediction (sets over the done runs)."""
    facts = {"detector": [], "prediction": []}
    for r in b.done:
        try:
            with open(os.path.join(b.out, "runs", r["run_id"], "summary.json")) as f:
                s = json.load(f)
        except (OSError, ValueError):
            continue
        for k in facts:
            if k in s and s[k] not in facts[k]:
                facts[k].append(s[k])
    return facts


def values_text(values, swept):
    if not values:
        return "n/a"
    return ", ".join(str(v) for v in values) + (" (swept)" if swept else "")


def write_header(f, b):
    """report.md's header: what was run, so a reader can reproduce and cite it."""
    rec = b.record
    facts = run_facts(b)
    sim = sorted({num(r.get("simulated_s")) for r in b.done if num(r.get("simulated_s")) is not None})
    ticks = sorted({num(r.get("ticks")) for r in b.done if num(r.get("ticks")) is not None})
    if len(sim) == 1 and len(ticks) == 1 and ticks[0]:
        length = "%g s simulated, %d steps of %g s" % (sim[0], ticks[0], round(sim[0] / ticks[0], 6))
    elif sim:
        length = "%g to %g s simulated" % (sim[0], sim[-1])
    else:
        length = "n/a"
    fixed = rec.get("fixed") or {}
    swept = ", ".join("%s: %s" % (p, ", ".join(b.values[p])) for p in b.sweep) or "nothing"
    n_done = len(b.done)
    f.write("# Batch report: %s\n\n" % rec.get("name", os.path.basename(os.path.normpath(b.out))))
    f.write("| | |\n|---|---|\n")
    for k, v in [("scenario (base)", scenario_text(rec)),
                 ("command", rec.get("command", "n/a")),
                 ("detector", values_text(facts["detector"], "detector" in b.sweep)),
                 ("prediction", values_text(facts["prediction"], "prediction" in b.sweep)),
                 ("run length", length),
                 ("seeds", "%d per combination (%s: %s), the same for every combination" % (
                     len(b.seeds), b.seed_key, seeds_text(b.seeds))),
                 ("swept", swept),
                 ("warm-up", "%g s of every run left out of every conflict statistic" % b.warmup if b.warmup else "none"),
                 ("fixed", ", ".join("%s: %s" % (k2, json.dumps(v2) if isinstance(v2, (dict, list)) else v2)
                                     for k2, v2 in fixed.items()) or "nothing"),
                 ("runs", "%d (%d done, %d not done)" % (len(b.runs), n_done, len(b.runs) - n_done))]:
        f.write("| %s | %s |\n" % (k, str(v).replace("|", "\\|")))
    f.write("\nEstimates are printed as estimate ± half-width (95 % CI, n=…): means over seeds with a Student "
            "t interval, paired differences on the same seeds likewise; shares (confirmed, recall) pooled "
            "over seeds with a Wilson 95 % interval and their counts.\n\n")
    f.write("Tables: [runs.csv](runs.csv) (one row per run), [summary.csv](summary.csv) "
            "(mean, standard deviation and 95%% confidence interval over seeds), [paired.csv](paired.csv) "
            "(differences on the same seeds)%s.\n\n" % (
                ", [hindsight.csv](hindsight.csv) (confirmed shares and recall, pooled over seeds)"
                if os.path.exists(os.path.join(b.out, "hindsight.csv")) else ""))


def write_hindsight(f, sweep, kinds, rows, warmup=0.0):
    """report.md's hindsight table: warnings per vehicle-km by kind, confirmed share (confirmed /
    judged) and recall (warned / events) with Wilson intervals, median lead time; n/a where
    nothing was counted."""
    def share(r, part, whole):
        k, n = num(r.get(part)), num(r.get(whole))
        return share_text(k or 0, n) if n else "n/a"
    f.write("## Hindsight (pooled over seeds; [hindsight.csv](hindsight.csv))\n\n"
            "Warnings per vehicle-km by kind (the mean of the runs' rates over the seeds%s); the confirmed share of each kind's warnings (what "
            "followed confirmed the conflict); the near misses' recall (warned at least the lead "
            "time before) and the median lead time; the same for the unsignalled line crossings and for the "
            "collisions, contacts with the bodies touching (the collider warned about the victim; SUMO's minGap "
            "violations are none). Shares with their Wilson 95 %% interval and "
            "k/n; n/a: nothing to count.\n\n"
            % (", after the %g s warm-up: warnings begun and events after it, over the distance driven after it" % warmup
               if warmup > 0 else ", as summary.csv's `warnings.per_vehicle_km_by_kind`"))
    cols = sweep + ["%s /veh-km" % k for k in kinds] + ["%s confirmed" % k for k in kinds] + \
        ["near-miss recall", "median lead (s)", "crossing recall", "median lead (s)",
         "collision recall", "median lead (s)"]
    per_km = {k: decimals([num(r.get(k + ".per_vehicle_km")) for r in rows]) for k in kinds}
    f.write("| " + " | ".join(cols) + " |\n")
    f.write("|" + "---|" * len(cols) + "\n")
    for r in rows:
        cells = [r[p] for p in sweep]
        for k in kinds:
            v = num(r.get(k + ".per_vehicle_km"))
            cells.append("n/a" if v is None else "%.*f" % (per_km[k], v))
        cells += [share(r, k + ".confirmed", k + ".judged") for k in kinds]
        for part, whole, lead in [("near_misses_warned", "near_misses", "near_miss_lead_median_s"),
                                  ("crossings_warned", "crossings", "crossing_lead_median_s"),
                                  ("collisions_warned", "collisions", "collision_lead_median_s")]:
            cells.append(share(r, part, whole))
            v = num(r.get(lead))
            cells.append("n/a" if v is None else "%.2f" % v)
        f.write("| " + " | ".join(cells) + " |\n")
    f.write("\n")


MEASURES = [("min_ttc", "min TTC (s)"), ("pet", "PET (s)"), ("drac", "DRAC (m/s²)"), ("max_s", "MaxS (m/s)"),
            ("delta_s", "DeltaS (m/s)"), ("dr", "DR (m/s²)"), ("max_d", "MaxD (m/s²)"),
            ("max_delta_v", "MaxDeltaV (m/s)")]


def write_conflicts(f, out, sweep):
    """report.md's SSAM section (conflicts.csv, conflicts_compared.csv): the conflicts by type and
    each SSAM measure per combination, then each swept value against the first (Welch)."""
    path = os.path.join(out, "conflicts.csv")
    if not os.path.exists(path):
        return
    cols, rows = read_csv(path)
    measures = [(m, lab) for m, lab in MEASURES if m + ".mean" in cols]
    f.write("## SSAM measures of the conflicts ([conflicts.csv](conflicts.csv))\n\n"
            "Conflicts: the runs' conflicts.csv pooled over the seeds of each combination, each conflict "
            "counted once (an unordered pair and one encounter whose box TTC fell to TTC*, whatever the "
            "detector; not the per-ego warnings). Each measure as mean ± half-width "
            "(95 % CI, n: the conflicts with a value).\n\n")
    head = sweep + ["runs", "conflicts", "rear-end", "lane change", "crossing", "pedestrian"] + [lab for _, lab in measures]
    f.write("| " + " | ".join(head) + " |\n|" + "---|" * len(head) + "\n")
    ds = {m: decimals([num(r.get(m + ".mean")) for r in rows]) for m, _ in measures}
    for r in rows:
        cells = [r[p] for p in sweep] + [r["runs"], r["conflicts"]] + [r.get(t, "0") for t in TYPES]
        for m, _ in measures:
            n = num(r.get(m + ".n"))
            cells.append(estimate(num(r.get(m + ".mean")), num(r.get(m + ".ci95")), int(n) if n is not None else None,
                                  ds[m]))
        f.write("| " + " | ".join(cells) + " |\n")
    path = os.path.join(out, "conflicts_compared.csv")
    if not os.path.exists(path):
        f.write("\n")
        return
    cols, comp = read_csv(path)
    if comp:
        f.write("\nTwo designs compared per measure ([conflicts_compared.csv](conflicts_compared.csv)), as "
                "SSAM's t-test: the difference of the means (compared − baseline) with Welch's 95 % interval "
                "and t. Conflicts of one run are not independent, so the interval is optimistic; for counts "
                "and rates the paired comparisons below are the sounder test.\n\n")
        head = ["compared"] + sweep + ["conflicts (vs baseline)"] + [lab for _, lab in measures]
        f.write("| " + " | ".join(head) + " |\n|" + "---|" * len(head) + "\n")
        for r in comp:
            cells = ["%s vs %s" % (r["compared"], r["baseline"])] + [r[p] for p in sweep] + \
                ["%s (%s)" % (r["conflicts"], r["baseline_conflicts"])]
            for m, _ in measures:
                diff, half, tv = num(r.get(m + ".diff_mean")), num(r.get(m + ".diff_ci95")), num(r.get(m + ".t"))
                d = ds[m]
                cells.append("n/a" if diff is None else "%+.*f ± %.*f (t=%.2f)" % (d, diff, d, half, tv)
                             if half is not None and tv is not None else "%+.*f (no interval)" % (d, diff))
            f.write("| " + " | ".join(cells) + " |\n")
    f.write("\n")



RATES = [("per_vehicle_km", "per vehicle-km", "exposure.vehicle_km", "vehicle-km"),
         ("per_hour", "per hour", "exposure.hours", "hours"),
         ("per_entering_vehicle", "per entering vehicle", "exposure.entering_vehicles", "entering vehicles")]


def write_headline(f, b):
    """report.md's lead (highway studies): the headline rate by SSAM type per combination and its
    paired differences by type with their 95 % intervals; then every rate with its exposure. Each
    rate has one definition (batch/src/rates.cpp), the one every table shows."""
    if not b.headline_types:
        return
    what = quantity(b.headline_types[0])[1]
    warm = ("the first %g s of every run (the warm-up) left out of every count, rate and exposure" % b.warmup
            if b.warmup else "no warm-up left out (`warmup:` 0)")
    f.write("## Headline: conflicts %s by type (`report.headline: %s`)\n\n" % (what, b.headline_name))
    f.write("A run's rate is its conflicts (its conflicts.csv: one per pair and encounter, counted once, "
            "below TTC*; not the per-ego warnings) that began after the warm-up, over its exposure after "
            "the warm-up; a combination's rate is the mean of its runs' rates over the seeds (Student t "
            "interval), a comparison's the mean of the seed-by-seed differences (paired t interval). "
            "Every table and figure of this report uses these definitions; %s.\n\n" % warm)
    cols = b.sweep + [label(m) for m in b.headline_types]
    f.write("| " + " | ".join(cols) + " |\n|" + "---|" * len(cols) + "\n")
    ds = {m: decimals([num(r.get(m + ".mean")) for r in b.summary]) for m in b.headline_types}
    for r in b.summary:
        cells = [r[p] for p in b.sweep]
        for m in b.headline_types:
            cells.append(estimate(num(r.get(m + ".mean")), num(r.get(m + ".ci95")), b.n(b.key(r), m), ds[m]))
        f.write("| " + " | ".join(cells) + " |\n")
    if b.paired:
        f.write("\n### Paired differences of the headline by type (compared − baseline, same seeds; "
                "[paired.csv](paired.csv))\n\n")
        cols = ["compared"] + b.sweep + ["pairs"] + ["difference in %s" % label(m) for m in b.headline_types]
        f.write("| " + " | ".join(cols) + " |\n|" + "---|" * len(cols) + "\n")
        ds = {m: decimals([num(r.get(m + ".diff_mean")) for r in b.paired]) for m in b.headline_types}
        for r in b.paired:
            cells = ["%s vs %s" % (r["compared"], r["baseline"])] + [r[p] for p in b.sweep] + [r["pairs"]]
            for m in b.headline_types:
                n = len(b.per_seed_differences(r, m))
                cells.append(estimate(num(r.get(m + ".diff_mean")), num(r.get(m + ".diff_ci95")), n, ds[m]))
            f.write("| " + " | ".join(cells) + " |\n")
    f.write("\n### Rates and exposure after the warm-up (mean over seeds; [summary.csv](summary.csv))\n\n")
    cols = b.sweep + ["conflicts per run"] + ["%s per run" % e for _, _, _, e in RATES] + \
        ["conflicts %s" % w for _, w, _, _ in RATES]
    f.write("| " + " | ".join(cols) + " |\n|" + "---|" * len(cols) + "\n")
    ms = ["counted.all"] + [x for _, _, x, _ in RATES] + ["rate.%s.all" % k for k, _, _, _ in RATES]
    ds = {m: decimals([num(r.get(m + ".mean")) for r in b.summary]) for m in ms}
    for r in b.summary:
        cells = [r[p] for p in b.sweep]
        for m in ms:
            cells.append(estimate(num(r.get(m + ".mean")), num(r.get(m + ".ci95")), b.n(b.key(r), m), ds[m]))
        f.write("| " + " | ".join(cells) + " |\n")
    f.write("\n")


def write_estimates(f, b):
    """The headline metric per combination, the paired comparisons and the collisions by action,
    each as estimate ± half-width (95 % CI, n=…), one precision per column."""
    m = b.headline
    if m:
        f.write("## %s by parameters\n\n" % label(m))
        f.write("Mean over seeds (`%s`).\n\n" % m)
        d = decimals([num(r.get(m + ".mean")) for r in b.summary])
        f.write("| " + " | ".join(b.sweep + [label(m)]) + " |\n")
        f.write("|" + "---|" * (len(b.sweep) + 1) + "\n")
        for r in b.summary:
            f.write("| " + " | ".join([r[p] for p in b.sweep] + [estimate(
                num(r.get(m + ".mean")), num(r.get(m + ".ci95")), b.n(b.key(r), m), d)]) + " |\n")
    # paired comparisons (paired.csv): each swept value against the key's first value on the same seeds
    metrics = [x for x in (m, b.collisions, find_col(b.metrics, r"^collisions_warned$")) if x]
    if b.paired and metrics:
        f.write("\n## Paired comparisons (same seeds; [paired.csv](paired.csv))\n\n")
        f.write("Differences run by run against the key's first value, the other keys held: "
                "the seeds' shared variation drops out. n: the pairs.\n\n")
        f.write("| compared | " + " | ".join(b.sweep) + " | pairs | " +
                " | ".join("difference in %s" % label(x) for x in metrics) + " |\n")
        f.write("|" + "---|" * (len(b.sweep) + 2 + len(metrics)) + "\n")
        ds = {x: decimals([num(r.get(x + ".diff_mean")) for r in b.paired]) for x in metrics}
        for r in b.paired:
            cells = ["%s vs %s" % (r["compared"], r["baseline"])] + [r[p] for p in b.sweep] + [r["pairs"]]
            for x in metrics:
                n = len(b.per_seed_differences(r, x))
                cells.append(estimate(num(r.get(x + ".diff_mean")), num(r.get(x + ".diff_ci95")), n, ds[x]))
            f.write("| " + " | ".join(cells) + " |\n")
    rows = collision_rows(b) if "action" in b.sweep and b.collisions else []
    if rows:
        others = [p for p in b.sweep if p != "action"]
        f.write("\n## %s by action\n\n" % label(b.collisions))
        d = decimals([x[2] for x in rows])
        f.write("| " + " | ".join(others + ["action", label(b.collisions)]) + " |\n")
        f.write("|" + "---|" * (len(others) + 2) + "\n")
        for g, action, mean, half, n in rows:
            f.write("| " + " | ".join(list(g) + [action, estimate(mean, half, n, d)]) + " |\n")


def save(fig, out, name):
    """Writes the figure at DPI, no wider than MAX_WIDTH_PX (a wider one is narrowed to it)."""
    w, h = fig.get_size_inches()
    if w * DPI > MAX_WIDTH_PX:
        fig.set_size_inches(MAX_WIDTH_PX / DPI, h)
        if not fig.get_constrained_layout():
            fig.tight_layout()
    fig.savefig(os.path.join(out, name), dpi=DPI)
    plt.close(fig)


def main(out):
    b = Batch(out)
    plots = []
    numeric_params = [p for p in b.sweep if all(num(r[p]) is not None for r in b.summary)]
    for x in numeric_params if b.headline else []:
        name = "metric_vs_%s.png" % re.sub(r"[^A-Za-z0-9]+", "_", x)
        save(metric_figure(b, x), out, name)
        plots.append((name, "%s against %s" % (label(b.headline), x)))
    fig = min_ttc_figure(b)
    if fig:
        save(fig, out, "min_ttc_distribution.png")
        plots.append(("min_ttc_distribution.png", "distribution of the conflicts' minimum TTC by SSAM type"))
    fig = collisions_figure(b)
    if fig:
        save(fig, out, "collisions_by_action.png")
        plots.append(("collisions_by_action.png", "%s with and without the brake action" % label(b.collisions)))
    fig = paired_figure(b)
    if fig:
        save(fig, out, "paired_differences.png")
        plots.append(("paired_differences.png", "paired differences on the same seeds, per seed and their mean"))
    maps = conflict_maps(out, b.runs, b.sweep, b.warmup)
    kinds, hrows = hindsight_rows(out)
    if hrows:
        save(hindsight_figure(b, kinds, hrows), out, "hindsight.png")
        plots.append(("hindsight.png", "confirmed share by warning kind and near-miss recall"))

    with open(os.path.join(out, "report.md"), "w") as f:
        write_header(f, b)
        write_headline(f, b)
        for name, title in plots:
            f.write("## %s\n\n![%s](%s)\n\n" % (title, title, name))
        if hrows:
            write_hindsight(f, b.sweep, kinds, hrows, warmup=b.warmup)
            write_misses(f, out, b.runs, b.sweep, warmup=b.warmup)
        write_ssm(f, b.sweep, b.summary, b.metrics)
        write_conflicts(f, out, b.sweep)
        if maps:
            f.write("## Conflict maps (one per parameter combination, all seeds)\n\n"
                    "Every conflict of conflicts.csv (after the warm-up) at its conflict point, coloured by "
                    "conflict type, sized by severity.\n\n")
            for name, lab in maps:
                f.write("### %s\n\n![conflict map, %s](%s.png) ([SVG](%s.svg))\n\n" % (lab, lab, name, name))
        write_estimates(f, b)
    return 0


if __name__ == "__main__":
    if len(sys.argv) != 2:
        sys.stderr.write("usage: plots.py BATCH_OUT_DIR\n")
        sys.exit(2)
    sys.exit(main(sys.argv[1]))
