#!/usr/bin/python3
"""Plots and report.md for a `stsim batch` output folder (runs.csv, summary.csv, runs/*/warnings.csv).

Uses Debian's python3-matplotlib. Called by `stsim batch`; can be re-run by hand:
    /usr/bin/python3 batch/plots.py OUT_DIR
"""
import csv
import importlib.util
import json
import math
import os
import re
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


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


def conflict_maps(out, runs, sweep):
    """One conflict map per parameter combination, all seeds together (highway runs whose
    warnings.csv has positions); the network from the runs' summary.json."""
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
        path = os.path.join(d, "warnings.csv")
        if not os.path.exists(path):
            continue
        with open(path, newline="") as f:
            header = next(csv.reader(f), [])
        if "x" not in header or "type" not in header:
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
        cm.main(args + [os.path.join(d, "warnings.csv") for d in dirs])
        maps.append((name, label))
    return maps


def hindsight_rows(out):
    path = os.path.join(out, "hindsight.csv")
    if not os.path.exists(path):
        return None, []
    header, rows = read_csv(path)
    kinds = [c[: -len(".confirmed_share")] for c in header if c.endswith(".confirmed_share")]
    return kinds, rows


def hindsight_plot(out, sweep):
    """Per parameter combination (pooled over seeds, hindsight.csv): each kind's confirmed share
    and the near misses' recall. A share of nothing is no bar, marked n/a: it is not 0."""
    kinds, rows = hindsight_rows(out)
    if not rows:
        return None
    labels = [", ".join(r[p] for p in sweep) or "all runs" for r in rows]
    series = [(k.replace("_", " ") + " confirmed", k + ".confirmed_share") for k in kinds]
    series.append(("near-miss recall", "near_miss_recall"))
    # a share with nothing to count in any combination (a kind never judged) gets no bars at all
    empty = [name for name, col in series if all(num(r.get(col)) is None for r in rows)]
    series = [(name, col) for name, col in series if name not in empty] or series[-1:]
    # one panel per share, the combinations down the side: readable for a few or for dozens
    fig, axes = plt.subplots(1, len(series), sharey=True, squeeze=False,
                             figsize=(2.4 * len(series) + 2.2, 0.26 * len(rows) + 1.6))
    ys = list(range(len(rows)))
    for si, (ax, (name, col)) in enumerate(zip(axes[0], series)):
        for y, r in zip(ys, rows):
            v = num(r.get(col))
            if v is None:
                ax.text(0.02, y, "n/a", va="center", fontsize=6, color="#777777")
            else:
                ax.barh(y, v, height=0.7, color="C%d" % si)
        ax.set_xlim(0, 1.0)
        ax.set_title(name, fontsize=8)
        ax.grid(alpha=0.3, axis="x")
        ax.tick_params(labelsize=7)
    axes[0][0].set_yticks(ys)
    axes[0][0].set_yticklabels(labels, fontsize=7)
    axes[0][0].invert_yaxis()
    fig.suptitle("share, pooled over seeds" + ("; n/a, nothing to count: " + ", ".join(empty) if empty else ""),
                 fontsize=8)
    fig.tight_layout()
    fig.savefig(os.path.join(out, "hindsight.png"), dpi=110)
    plt.close(fig)
    return ("hindsight.png", "confirmed share by warning kind and near-miss recall"), kinds, rows


def write_hindsight(f, sweep, kinds, rows):
    """report.md's hindsight table: warnings per vehicle-km by kind, confirmed share (confirmed /
    judged), near-miss recall (warned / events), median lead time; n/a where nothing was counted."""
    def share(r, part, whole, col):
        v = num(r.get(col))
        return "n/a" if v is None else "%.3f (%d/%d)" % (v, num(r.get(part)), num(r.get(whole)))
    f.write("## Hindsight (pooled over seeds; [hindsight.csv](hindsight.csv))\n\n"
            "Warnings per vehicle-km by kind; the confirmed share of each kind's warnings (what "
            "followed confirmed the conflict); the near misses' recall (warned at least the lead "
            "time before) and the median lead time; the same for the unsignalled line crossings and for SUMO's "
            "collisions (the collider warned about the victim). n/a: nothing to count.\n\n")
    cols = sweep + ["%s /veh-km" % k for k in kinds] + ["%s confirmed" % k for k in kinds] + \
        ["near-miss recall", "median lead (s)", "crossing recall", "median lead (s)",
         "collision recall", "median lead (s)"]
    f.write("| " + " | ".join(cols) + " |\n")
    f.write("|" + "---|" * len(cols) + "\n")
    for r in rows:
        cells = [r[p] for p in sweep]
        cells += [fmt(r.get(k + ".per_vehicle_km")) or "n/a" for k in kinds]
        cells += [share(r, k + ".confirmed", k + ".judged", k + ".confirmed_share") for k in kinds]
        cells.append(share(r, "near_misses_warned", "near_misses", "near_miss_recall"))
        cells.append(fmt(r.get("near_miss_lead_median_s")) or "n/a")
        cells.append(share(r, "crossings_warned", "crossings", "crossing_recall"))
        cells.append(fmt(r.get("crossing_lead_median_s")) or "n/a")
        cells.append(share(r, "collisions_warned", "collisions", "collision_recall"))
        cells.append(fmt(r.get("collision_lead_median_s")) or "n/a")
        f.write("| " + " | ".join(cells) + " |\n")
    f.write("\n")


def write_misses(f, out, runs, sweep, samples=5):
    """report.md's missed events: per parameter combination, the near misses and unsignalled
    crossings (each run's events.csv) that were not warned the lead time ahead, counted, and the
    first few of them to look at (late: warned, but less than the lead time ahead)."""
    groups = {}
    for r in runs:
        path = os.path.join(out, "runs", r["run_id"], "events.csv")
        if r["status"] != "done" or not os.path.exists(path):
            continue
        g = groups.setdefault(tuple(r[p] for p in sweep), {"events": 0, "missed": []})
        _, rows = read_csv(path)
        g["events"] += len(rows)
        g["missed"] += [dict(e, run=r["run_id"]) for e in rows if e["warned"] != "1"]
    if not any(g["missed"] for g in groups.values()):
        return

    def cell(text):  # a marker's name joins its two lanes with "|"
        return text.replace("|", "\\|")
    f.write("## Missed events (from each run's events.csv)\n\n"
            "Near misses and unsignalled crossings not warned the lead time ahead, per combination, and "
            "the first %d of them: late (warned, but less than the lead time ahead) or not warned at all.\n\n" % samples)
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


def main(out):
    runs_header, runs = read_csv(os.path.join(out, "runs.csv"))
    sum_header, summary = read_csv(os.path.join(out, "summary.csv"))
    # parameters sit between "status" and "wall_seconds"; the last of them is the seed key
    params = runs_header[runs_header.index("status") + 1: runs_header.index("wall_seconds")]
    sweep, seed_key = params[:-1], params[-1]
    metrics = [c[: -len(".mean")] for c in sum_header if c.endswith(".mean")]
    numeric_params = [p for p in sweep if all(num(r[p]) is not None for r in summary)]
    series_param = "detector" if "detector" in sweep else None
    plots = []

    # 1. the headline metric against each numeric swept parameter, one line per detector
    headline = find_col(metrics, r"per_vehicle_km.*total|total.*per_vehicle_km", r"per_vehicle_km",
                        r"collision_checks$", r"warnings")
    headline = headline or (metrics[0] if metrics else None)
    for x in numeric_params:
        if headline is None:
            break
        fig, ax = plt.subplots(figsize=(6, 4))
        groups = {}
        for r in summary:
            key = r[series_param] if series_param else "all"
            groups.setdefault(key, []).append(r)
        for key, rows in sorted(groups.items()):
            rows = [r for r in rows if num(r.get(headline + ".mean")) is not None]
            # average over the other swept parameters is not meaningful: plot each combination
            rows.sort(key=lambda r: num(r[x]))
            xs = [num(r[x]) for r in rows]
            ys = [num(r[headline + ".mean"]) for r in rows]
            es = [num(r[headline + ".ci95"]) or 0.0 for r in rows]
            ax.errorbar(xs, ys, yerr=es, marker="o", capsize=3, label=str(key))
        ax.set_xlabel(x)
        ax.set_ylabel(headline + " (mean, 95% CI)")
        ax.grid(alpha=0.3)
        if series_param:
            ax.legend(title=series_param)
        name = "metric_vs_%s.png" % re.sub(r"[^A-Za-z0-9]+", "_", x)
        fig.tight_layout()
        fig.savefig(os.path.join(out, name), dpi=110)
        plt.close(fig)
        plots.append((name, "%s against %s" % (headline, x)))

    # 2. distribution of the minimum TTC per warning episode, per detector
    ttc_by = {}
    for r in runs:
        if r["status"] != "done":
            continue
        path = os.path.join(out, "runs", r["run_id"], "warnings.csv")
        if not os.path.exists(path):
            continue
        with open(path, newline="") as f:
            rd = csv.DictReader(f)
            col = find_col(rd.fieldnames or [], r"^min_ttc", r"min_ttc")
            if not col:
                continue
            key = r[series_param] if series_param else "all"
            for w in rd:
                v = num(w[col])
                if v is not None:
                    ttc_by.setdefault(key, []).append(v)
    if ttc_by:
        fig, ax = plt.subplots(figsize=(6, 4))
        hi = max(max(v) for v in ttc_by.values())
        bins = [hi * i / 30 for i in range(31)] if hi > 0 else 10
        for key, vals in sorted(ttc_by.items()):
            ax.hist(vals, bins=bins, histtype="step", linewidth=1.5, label="%s (%d)" % (key, len(vals)))
        ax.set_xlabel("minimum TTC per episode (s)")
        ax.set_ylabel("episodes")
        ax.grid(alpha=0.3)
        ax.legend(title=series_param or "")
        fig.tight_layout()
        fig.savefig(os.path.join(out, "min_ttc_distribution.png"), dpi=110)
        plt.close(fig)
        plots.append(("min_ttc_distribution.png", "distribution of the minimum TTC per warning episode"))

    # 3. SUMO collisions with and without the brake action, per combination of the other swept
    #    parameters (mean and 95% CI over seeds from summary.csv, each run's count as a dot)
    coll = find_col(metrics, r"^sumo_collisions$", r"sumo.*collisions", r"collisions$")
    collision_rows = []
    if "action" in sweep and coll:
        others = [p for p in sweep if p != "action"]
        actions = sorted({r["action"] for r in summary}, key=lambda a: (a != "none", a))
        groups = sorted({tuple(r[p] for p in others) for r in summary},
                        key=lambda g: [num(v) if num(v) is not None else v for v in g])
        fig, ax = plt.subplots(figsize=(max(5, 1.6 * len(groups) + 2), 4))
        width = 0.8 / max(1, len(actions))
        for ai, action in enumerate(actions):
            xs, ys, es = [], [], []
            for gi, g in enumerate(groups):
                row = next((r for r in summary if r["action"] == action and
                            tuple(r[p] for p in others) == g), None)
                if row is None:
                    continue
                m, e = num(row.get(coll + ".mean")), num(row.get(coll + ".ci95")) or 0.0
                if m is None:
                    continue
                x = gi + (ai - (len(actions) - 1) / 2) * width
                xs.append(x)
                ys.append(m)
                es.append(e)
                collision_rows.append((g, action, m, e))
                dots = [num(r[coll]) for r in runs if r["status"] == "done" and r["action"] == action and
                        tuple(r[p] for p in others) == g and num(r[coll]) is not None]
                ax.plot([x] * len(dots), dots, "k.", alpha=0.4)
            ax.bar(xs, ys, width=width * 0.9, yerr=es, capsize=3, label=action,
                   color="#999999" if action == "none" else "#cc3333" if ai == 1 else None)
        ax.set_xticks(range(len(groups)))
        ax.set_xticklabels([", ".join("%s=%s" % (p, v) for p, v in zip(others, g)) or "all" for g in groups])
        ax.set_ylabel(coll + " per run (mean, 95% CI)")
        ax.legend(title="action")
        ax.grid(alpha=0.3, axis="y")
        fig.tight_layout()
        fig.savefig(os.path.join(out, "collisions_by_action.png"), dpi=110)
        plt.close(fig)
        plots.append(("collisions_by_action.png", "%s with and without the brake action" % coll))

    maps = conflict_maps(out, runs, sweep)
    hindsight = hindsight_plot(out, sweep)
    if hindsight:
        plots.append(hindsight[0])

    done = sum(1 for r in runs if r["status"] == "done")
    with open(os.path.join(out, "report.md"), "w") as f:
        f.write("# Batch report\n\n")
        f.write("%d runs (%d done, %d not done); swept: %s; seeds per combination: %d.\n\n" % (
            len(runs), done, len(runs) - done, ", ".join(sweep) or "nothing",
            len({r[seed_key] for r in runs})))
        f.write("Tables: [runs.csv](runs.csv) (one row per run), [summary.csv](summary.csv) "
                "(mean, standard deviation and 95%% confidence interval over seeds), [paired.csv](paired.csv) "
                "(differences on the same seeds)%s.\n\n" % (
                    ", [hindsight.csv](hindsight.csv) (confirmed shares and recall, pooled over seeds)"
                    if hindsight else ""))
        for name, title in plots:
            f.write("## %s\n\n![%s](%s)\n\n" % (title, title, name))
        if hindsight:
            write_hindsight(f, sweep, hindsight[1], hindsight[2])
            write_misses(f, out, runs, sweep)
        write_ssm(f, sweep, summary, metrics)
        if maps:
            f.write("## Conflict maps (one per parameter combination, all seeds)\n\n"
                    "Every warning at the ego's position at its minimum TTC, coloured by conflict type, "
                    "sized by severity.\n\n")
            for name, label in maps:
                f.write("### %s\n\n![conflict map, %s](%s.png) ([SVG](%s.svg))\n\n" % (label, label, name, name))
        if headline:
            f.write("## %s by parameters\n\n" % headline)
            f.write("| " + " | ".join(sweep + ["mean", "95% CI"]) + " |\n")
            f.write("|" + "---|" * (len(sweep) + 2) + "\n")
            for r in summary:
                f.write("| " + " | ".join([r[p] for p in sweep] + [fmt(r.get(headline + ".mean")),
                                                                    fmt(r.get(headline + ".ci95"))]) + " |\n")
        # paired comparisons (paired.csv): the headline metric and SUMO's collisions, each swept
        # value against the key's first value on the same seeds
        paired_path = os.path.join(out, "paired.csv")
        paired_metrics = [m for m in (headline, coll, find_col(metrics, r"^collisions_warned$")) if m]
        if os.path.exists(paired_path) and paired_metrics:
            _, paired = read_csv(paired_path)
            if paired:
                f.write("\n## Paired comparisons (same seeds; [paired.csv](paired.csv))\n\n")
                f.write("Differences run by run against the key's first value, the other keys held: "
                        "the seeds' shared variation drops out.\n\n")
                f.write("| compared | " + " | ".join(sweep) + " | pairs | " +
                        " | ".join("%s difference (95%% CI)" % m for m in paired_metrics) + " |\n")
                f.write("|" + "---|" * (len(sweep) + 2 + len(paired_metrics)) + "\n")
                for r in paired:
                    cells = ["%s vs %s" % (r["compared"], r["baseline"])] + [r[p] for p in sweep] + [r["pairs"]]
                    for m in paired_metrics:
                        cells.append("%s ± %s" % (fmt(r.get(m + ".diff_mean")), fmt(r.get(m + ".diff_ci95"))))
                    f.write("| " + " | ".join(cells) + " |\n")
        if collision_rows:
            others = [p for p in sweep if p != "action"]
            f.write("\n## %s by action\n\n" % coll)
            f.write("| " + " | ".join(others + ["action", "mean", "95% CI"]) + " |\n")
            f.write("|" + "---|" * (len(others) + 3) + "\n")
            for g, action, m, e in collision_rows:
                f.write("| " + " | ".join(list(g) + [action, fmt(m), fmt(e)]) + " |\n")
    return 0


if __name__ == "__main__":
    if len(sys.argv) != 2:
        sys.stderr.write("usage: plots.py BATCH_OUT_DIR\n")
        sys.exit(2)
    sys.exit(main(sys.argv[1]))
