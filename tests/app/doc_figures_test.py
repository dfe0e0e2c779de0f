#!/usr/bin/env python3
"""The figures the READMEs quote cannot drift from what stsim gives.

Each quoted figure below is a template over what a named command writes (the command the README
itself names). The test runs each command once, fills the templates with the values it wrote and
checks that every README holds the filled text verbatim: a change that moves a figure fails here,
naming the file, the text it should now read and the command that makes it.

  usage: doc_figures_test.py STSIM SOURCE_DIR [--long | --slow] [--keep DIR] [--print]
  --print prints the filled texts instead of checking (to update a README by hand).
  --long  the experiments' figures instead (networks/experiments/README.md: the incident study, two
          batches of 40 runs, and the demand sweep, 75 runs: about 5 minutes on 2 cores)
  --slow  the brake study's (two batches of 180 runs) and the real networks' (48 runs): about 12
          minutes on 2 cores; not in the suite

Needs SUMO (the commands are live highway runs, about 15 s each).
"""
import math
import csv
import json
import os
import shutil
import subprocess
import sys
import tempfile


def thin(n):
    """1 234 567: the READMEs' thousands separator (a space), below 10 000 none."""
    n = int(n)
    return "{:,}".format(n).replace(",", " ") if n >= 10000 or n <= -10000 else "%d" % n


def sci(x):
    """1.4e-6, as the READMEs write it (Python writes 1.4e-06)."""
    mant, exp = ("%.1e" % x).split("e")
    return "%se%d" % (mant, int(exp))


def thousands(n):
    """1 234: a space from 1 000 on (as the READMEs' tables write counts)."""
    return "{:,}".format(int(n)).replace(",", " ")


# the commands, by name: (arguments after stsim, relative to the source dir)
COMMANDS = {
    # README.md's main job, cosim/README.md's validation table
    "main": ["highway", "networks/motorway/scenario.yaml", "--validate-ssm", "--no-map"],
    "main_concentric": ["highway", "networks/motorway/scenario.yaml", "--detector", "concentric", "--no-map"],
    "main_box": ["highway", "networks/motorway/scenario.yaml", "--detector", "box", "--no-map"],
    # cosim/README.md's lane drop (the shipped merge) against SSM
    "lanedrop": ["highway", "networks/sublane/scenario.yaml", "--validate-ssm", "--no-map"],
    # ... and its right-angle crossing, where SSM has PETs
    # (as SSM predicts them: the minor road's cars on at their speed, not giving way)
    "crossing": ["highway", "tests/data/crossing/crossing.sumocfg", "--validate-ssm", "--set", "priority_rules=false",
                 "--no-map"],
    # networks/onramp/README.md and networks/lanedrop/README.md: the hand-built ramps against SSM
    "onramp_short": ["highway", "networks/onramp/short.yaml", "--validate-ssm", "--no-map"],
    "onramp_long": ["highway", "networks/onramp/long.yaml", "--validate-ssm", "--no-map"],
    "ramp_lanedrop": ["highway", "networks/lanedrop/scenario.yaml", "--validate-ssm", "--no-map"],
    # the junction networks against SSM (their READMEs' "Against SUMO's SSM device")
    "actuated": ["highway", "networks/actuated/scenario.yaml", "--validate-ssm", "--no-map"],
    "roundabout": ["highway", "networks/roundabout/scenario.yaml", "--validate-ssm", "--no-map"],
    "bicycles": ["highway", "networks/bicycles/scenario.yaml", "--validate-ssm", "--no-map"],
    "intersection": ["highway", "networks/intersection/scenario.yaml", "--validate-ssm", "--no-map"],
    "crosswalk": ["highway", "networks/crosswalk/scenario.yaml", "--validate-ssm", "--no-map"],
}
# which of them each README quotes, in the same sentences (network_figures)
NETWORK_READMES = {
    "actuated": "networks/actuated/README.md",
    "roundabout": "networks/roundabout/README.md",
    "bicycles": "networks/bicycles/README.md",
}
# the junction networks whose READMEs say how the conflicts were confirmed (encounter_figures)
ENCOUNTER_READMES = dict(NETWORK_READMES, intersection="networks/intersection/README.md",
                         crosswalk="networks/crosswalk/README.md")


# the long figures: batches, by name (the experiment file, fixed keys added to its own, the
# swept keys that name a row of its summary.csv); --long runs the first group (about 5 minutes on
# 2 cores), --slow the second (about 12 minutes, not in the test suite)
BATCHES = {
    "incident": ("networks/experiments/incident_study.yaml", {}, ("action",)),
    "incident_contacts": ("networks/experiments/incident_study.yaml", {"collision_mingap_factor": 0}, ("action",)),
    "demand_sweep": ("networks/experiments/demand_sweep.yaml", {}, ("demand_scale", "detector")),
    "accel_lane": ("networks/experiments/accel_lane.yaml", {}, ("base",)),
}
SLOW_BATCHES = {
    "brake": ("networks/experiments/brake_study.yaml", {}, ("penetration", "action")),
    "brake_contacts": ("networks/experiments/brake_study.yaml", {"collision_mingap_factor": 0},
                       ("penetration", "action")),
    "real_networks": ("networks/experiments/real_networks.yaml", {}, ("base", "prediction", "detector")),
}


def run_batch(stsim, src, work, name):
    """summary.csv and paired.csv of an experiment: {"row key": {column: value}}, the row key its
    swept values joined by "/" ("none", "1.0/five"); "diff" (a one-action study's paired
    difference) or "diff/<other keys>"; "runs": runs.csv's rows as read."""
    exp, extra, keys = {**BATCHES, **SLOW_BATCHES}[name]
    path = os.path.join(src, exp)
    if extra:
        # the same experiment with more fixed keys: a copy beside the original's base
        with open(path) as f:
            text = f.read()
        text = text.replace("base: ../", "base: %s/" % os.path.dirname(os.path.dirname(path)))
        text = text.replace("fixed:\n", "fixed:\n" + "".join("  %s: %s\n" % kv for kv in extra.items()))
        path = os.path.join(work, name + ".yaml")
        with open(path, "w") as f:
            f.write(text)
    out = os.path.join(work, name)
    p = subprocess.run([stsim, "batch", path, "--jobs", str(os.cpu_count() or 1), "--no-plots", "--out", out],
                       cwd=work, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, timeout=1800)
    if p.returncode != 0:
        sys.exit("FAIL stsim batch %s: exit %d\n%s" % (exp, p.returncode, p.stderr))
    def numbers(r):
        out = {}
        for k, v in r.items():
            try:
                out[k] = float(v)
            except (TypeError, ValueError):
                pass
        return out

    res = {}
    with open(os.path.join(out, "summary.csv"), newline="") as f:
        for r in csv.DictReader(f):
            res["/".join(r[k] for k in keys)] = numbers(r)
    with open(os.path.join(out, "paired.csv"), newline="") as f:
        for r in csv.DictReader(f):
            # the action studies compare the actions; a study of designs compares its bases
            if r["compared"] != ("base" if keys == ("base",) else "action"):
                continue
            rest = [r[k] for k in keys if k not in ("action", "base")]
            res["/".join(["diff"] + rest)] = numbers(r)
    with open(os.path.join(out, "runs.csv"), newline="") as f:
        res["runs"] = list(csv.DictReader(f))
    res["hindsight"] = {}
    with open(os.path.join(out, "hindsight.csv"), newline="") as f:
        for r in csv.DictReader(f):
            res["hindsight"]["/".join(r[k] for k in keys)] = numbers(r)
    return res


def rnd(x):
    """Half up, as the READMEs round counts (Python's round is half to even)."""
    return int(math.floor(x + 0.5))


def long_figures(r):
    inc, con = r["incident"], r["incident_contacts"]
    none, brake, diff = inc["none"], inc["brake"], inc["diff"]

    def pm(row, key, d, diff=False):
        return "%.*f ± %.*f" % (d, row[key + (".diff_mean" if diff else ".mean")], d,
                                row[key + (".diff_ci95" if diff else ".ci95")])

    readme = "networks/experiments/README.md"
    c_none, c_brake, c_diff = con["none"], con["brake"], con["diff"]
    return [
        (readme, "| SUMO collisions (gap below minGap) | %s | %s | **%s** |"
         % (pm(none, "sumo_collisions", 1), pm(brake, "sumo_collisions", 1), pm(diff, "sumo_collisions", 1, True))),
        (readme, "| physical contacts (`collision_mingap_factor: 0`, same seeds) | %s | %s | **%s** |"
         % (pm(c_none, "sumo_collisions", 2), pm(c_brake, "sumo_collisions", 2), pm(c_diff, "sumo_collisions", 2, True))),
        (readme, "| contact reports (steps touching) | %d | %d | %d ± %d |"
         % (rnd(none["sumo_collision_steps.mean"]), rnd(brake["sumo_collision_steps.mean"]),
            rnd(diff["sumo_collision_steps.diff_mean"]), rnd(diff["sumo_collision_steps.diff_ci95"]))),
        (readme, "| contacts stsim sees (the bodies touching, same runs) | %.2f | %.2f | |"
         % (none["contacts.mean"], brake["contacts.mean"])),
        (readme, "| contacts whose collider was warning about the victim | %.1f (%d %%) | %.1f (%d %%) | |"
         % (none["collisions_warned.mean"], rnd(100 * none["collisions_warned.mean"] / none["contacts.mean"]),
            brake["collisions_warned.mean"], rnd(100 * brake["collisions_warned.mean"] / brake["contacts.mean"]))),
        (readme, "| mean warning lead time of those (s) | %.2f | %.2f | |"
         % (none["collision_lead_time_mean_s.mean"], brake["collision_lead_time_mean_s.mean"])),
        (readme, "| brake commands | %d | %d | |" % (rnd(none["brake_commands.mean"]), rnd(brake["brake_commands.mean"]))),
        (readme, "the same 40 runs give %s contacts per run without braking and %s with it, paired %s,"
         % (pm(c_none, "sumo_collisions", 2), pm(c_brake, "sumo_collisions", 2), pm(c_diff, "sumo_collisions", 2, True))),
    ]


def accel_lane_figures(r):
    """networks/onramp/README.md: the two designs' rear-end conflicts per vehicle-km and their
    paired difference (accel_lane.yaml's report.md headline)."""
    a = r["accel_lane"]
    short, long_, diff = a["short"], a["long"], a["diff"]
    key = "rate.per_vehicle_km.rear_end"

    def pm(row, d, paired=False):
        return "%.*f ± %.*f" % (d, row[key + (".diff_mean" if paired else ".mean")], d,
                                row[key + (".diff_ci95" if paired else ".ci95")])
    return [("networks/onramp/README.md", "| rear-end conflicts per vehicle-km | %s | %s | **%s** (%d seeds) |"
             % (pm(short, 4), pm(long_, 4), pm(diff, 4, True), rnd(diff["pairs"])))]


def demand_figures(r):
    d = r["demand_sweep"]
    scales = ["0.5", "0.75", "1.0", "1.25", "1.5"]
    dets = ["concentric", "five", "box"]
    readme = "networks/experiments/README.md"

    def pm(row, key, digits):
        return "%.*f ± %.*f" % (digits, row[key + ".mean"], digits, row[key + ".ci95"])

    def span(det, digits):
        v = [d[s + "/" + det]["warnings.per_vehicle_km_by_type.proximity.mean"] for s in scales]
        return "none" if max(v) == 0 else "%.*f to %.*f" % (digits, min(v), digits, max(v))

    rows = [(readme, "| %s | %s | %s |" % (
        s, " | ".join(pm(d[s + "/" + k], "warnings.per_vehicle_km", 2) for k in dets),
        " | ".join(pm(d[s + "/" + k], "warnings.per_vehicle_km_by_type.rear_end", 3) for k in dets)))
        for s in scales]
    def overlap(s):
        key = "warnings.per_vehicle_km_by_type.rear_end"
        lo = [d[s + "/" + k][key + ".mean"] - d[s + "/" + k][key + ".ci95"] for k in dets]
        hi = [d[s + "/" + k][key + ".mean"] + d[s + "/" + k][key + ".ci95"] for k in dets]
        return max(lo) <= min(hi)

    agree = all(overlap(s) for s in scales)
    rear = lambda s: "%.3f" % d[s + "/five"]["warnings.per_vehicle_km_by_type.rear_end.mean"]
    veh = lambda s: "%d" % rnd(d[s + "/five"]["vehicles.mean"])
    return rows + [
        (readme, "the concentric circles, whose whole-car circles span the next lane, raise %s per vehicle-km, "
         "the five-circle side zones %s, the box %s." % (span("concentric", 1), span("five", 2), span("box", 2))),
        (readme, "On the conflicts they agree within their intervals at every demand." if agree else
         "On the conflicts their intervals part at some demand."),
        (readme, "(five-circle: %s rear-end conflicts per vehicle-km at 1.0, %s at 1.25)" % (rear("1.0"), rear("1.25"))),
        (readme, "(scale 1.5 inserts %s vehicles against %s at 1.25 and %s at 1.0)" % (veh("1.5"), veh("1.25"),
                                                                                        veh("1.0"))),
    ]


def brake_figures(r):
    b, c = r["brake"], r["brake_contacts"]
    levels = ["0.5", "0.75", "1.0"]
    readme = "networks/experiments/README.md"

    def pm(row, key, digits, diff=False):
        sfx = (".diff_mean", ".diff_ci95") if diff else (".mean", ".ci95")
        return "%.*f ± %.*f" % (digits, row[key + sfx[0]], digits, row[key + sfx[1]])

    def fewer_more(level):
        by = {}
        for run in b["runs"]:
            if run["penetration"] == level and run["status"] == "done":
                by.setdefault(run["seed"], {})[run["action"]] = float(run["sumo_collisions"])
        pairs = [v for v in by.values() if len(v) == 2]
        if len(pairs) != 30:
            sys.exit("FAIL brake study: %d paired seeds at %s equipped, 30 expected" % (len(pairs), level))
        return (sum(v["brake"] < v["none"] for v in pairs), sum(v["brake"] > v["none"] for v in pairs))

    rows = []
    for lv in levels:
        none, brake, diff = b[lv + "/none"], b[lv + "/brake"], b["diff/" + lv]
        f, m = fewer_more(lv)
        rows.append((readme, "| %d %% | %s | %s | %s | %d / %d | %.1f / %.1f |" % (
            rnd(100 * float(lv)), pm(none, "sumo_collisions", 2), pm(brake, "sumo_collisions", 2),
            pm(diff, "sumo_collisions", 2, True), f, m, none["sumo_collision_steps.mean"],
            brake["sumo_collision_steps.mean"])))

    def drop(key):
        v = [100 * (1 - b[lv + "/brake"][key + ".mean"] / b[lv + "/none"][key + ".mean"]) for lv in levels]
        return "%d to %d %%" % (rnd(min(v)), rnd(max(v)))

    zero_in_all = all(b["diff/" + lv]["sumo_collisions.diff_mean"] - b["diff/" + lv]["sumo_collisions.diff_ci95"]
                      <= 0 <= b["diff/" + lv]["sumo_collisions.diff_mean"] + b["diff/" + lv]["sumo_collisions.diff_ci95"]
                      for lv in levels)
    cb = [c[lv + "/brake"]["sumo_collisions.mean"] for lv in levels]
    cd = [c["diff/" + lv]["sumo_collisions.diff_mean"] for lv in levels]
    ch = [c["diff/" + lv]["sumo_collisions.diff_ci95"] for lv in levels]
    half = "%.2f" % ch[0] if len({"%.2f" % h for h in ch}) == 1 else "%.2f to %.2f" % (min(ch), max(ch))
    return rows + [
        (readme, "Braking lowers the collision count by %s and the contact time by %s" % (
            drop("sumo_collisions"), drop("sumo_collision_steps"))),
        (readme, "at 30 seeds the difference is %s" % (
            "not significant** (every paired CI contains 0)" if zero_in_all else "significant at some rate**")),
        (readme, "the same 180 runs then give %s contacts per run without braking and %.2f to %.2f with it "
         "(paired differences %.2f to %.2f, each ± %s)" % (
             pm(c["1.0/none"], "sumo_collisions", 2), min(cb), max(cb), max(cd), min(cd), half)),
        (readme, "(the mean warning lead time before a collision, without braking, is %.1f s)" % (
            b["1.0/none"]["collision_lead_time_mean_s.mean"])),
    ]


def real_figures(r):
    """networks/experiments/README.md's real-network table and what its prose quotes of it."""
    h, s = r["real_networks"]["hindsight"], r["real_networks"]
    readme = "networks/experiments/README.md"
    nets = ["A10KW", "highway", "grid6", "cross", "motorway", "sublane", "ring", "incident"]
    dets = ["five", "box", "concentric"]
    hs = lambda net, pred, det: h["%s/%s/%s" % (net, pred, det)]

    def road_lines(net, pred):
        x = hs(net, pred, "five")
        return x["curb.per_vehicle_km"] + x["lane_marker.per_vehicle_km"]

    def small(x):
        return "0" if x == 0 else ("%.2g" if x < 0.1 else "%.3g") % x

    def confirmed(net, pred):
        x = hs(net, pred, "box")
        return "%d/%d (%.2f)" % (x["vehicle.confirmed"], x["vehicle.judged"], x["vehicle.confirmed_share"])

    def near(net, pred):
        if hs(net, pred, "five")["near_misses"] == 0:
            return "none, none, none"
        return ", ".join("%d/%d" % (hs(net, pred, d)["near_misses_warned"], hs(net, pred, d)["near_misses"])
                         for d in dets)

    def crossings(net, pred):
        x = hs(net, pred, "five")
        return "none" if x["crossings"] == 0 else "%d/%d" % (x["crossings_warned"], x["crossings"])

    rows = []
    for net in nets:
        a, b = road_lines(net, "straight"), road_lines(net, "road")
        fewer = "none left" if b == 0 else "%dx fewer" % rnd(a / b)
        rows.append((readme, "| %s | %.2f -> %s (%s) | %s -> %s | %s -> %s | %s -> %s |" % (
            net, a, small(b), fewer, confirmed(net, "straight"), confirmed(net, "road"), near(net, "straight"),
            near(net, "road"), crossings(net, "straight"), crossings(net, "road"))))

    def all_same(net, key):
        v = {(p, d): hs(net, p, d)[key] for p in ("straight", "road") for d in dets}
        return v[("road", "five")] if len(set(v.values())) == 1 else float("nan")

    share = lambda net, pred: hs(net, pred, "box")["vehicle.confirmed_share"]
    tenth, whole = (lambda x: "%.1fx" % x), (lambda x: "%dx" % rnd(x))

    def rise(net, text):
        # a network with no confirmed box warning under `straight` has no ratio: say what it rose
        # from, or that none is confirmed either way
        before, after = share(net, "straight"), share(net, "road")
        if before == 0:
            return "none is confirmed either way" if after == 0 else "from 0"
        return "it rises " + text(after / before)

    nm = lambda net: [hs(net, "road", d)["near_misses_warned"] for d in dets]
    either = lambda xs: "%d" % min(xs) if min(xs) == max(xs) else "%d or %d" % (min(xs), max(xs))
    ssm = [s["motorway/%s/box" % p] for p in ("straight", "road")]
    below = [x["ssm.detectors.%s.ssm_conflicts_below_safe_time.mean" % d] for x in ssm for d in dets]
    recalled = [x["ssm.detectors.%s.recalled.mean" % d] for x in ssm for d in dets]
    sub = hs("sublane", "road", "five")
    return rows + [
        (readme, "the motorway's %d of %d, the incident run's %s (%.1f s ahead; %.1f s by the concentric circles)" % (
             all_same("motorway", "collisions_warned"), all_same("motorway", "collisions"),
             "%d of %d" % (hs("incident", "road", "five")["collisions_warned"], hs("incident", "road", "five")["collisions"]),
             hs("incident", "road", "five")["collision_lead_median_s"],
             hs("incident", "road", "concentric")["collision_lead_median_s"])),
        (readme, "the box's rectangle reaches a line a little sooner than the circles, %.3f against %.3f per veh-km on "
         "the motorway" % (hs("motorway", "road", "box")["curb.per_vehicle_km"] +
                          hs("motorway", "road", "box")["lane_marker.per_vehicle_km"], road_lines("motorway", "road"))),
        (readme, "SSM validation on the motorway, both predictions: %.3f %% of the box TTCs within 0.02 s of SSM's, "
         "and %s SSM conflicts below the safe time recalled by every detector" % (
             100 * min(x["ssm.following.within_fraction.mean"] for x in ssm),
             "%d of %d" % (min(recalled), max(below)) if min(recalled) == max(recalled) and
             min(below) == max(below) else "not all")),
        (readme, "the box detector's confirmed share: on A10KW %s, on grid6 %s, on `highway` %s and on cross %s "
         "(both on a few warnings under `road`: %s and %s), and on the motorway it does not fall (%.2f -> %.2f)" % (
             rise("A10KW", tenth), rise("grid6", tenth), rise("highway", whole), rise("cross", whole),
             confirmed("highway", "road").split(" ")[0], confirmed("cross", "road").split(" ")[0],
             share("motorway", "straight"), share("motorway", "road"))),
        (readme, "Near misses under `road`: every detector warns %s of A10KW's %d and %s of grid6's %d." % (
            either(nm("A10KW")), hs("A10KW", "road", "five")["near_misses"], either(nm("grid6")),
            hs("grid6", "road", "five")["near_misses"])),
        (readme, "The box's %d/%d on the sublane network" % (hs("sublane", "road", "box")["near_misses_warned"],
                                                            hs("sublane", "road", "box")["near_misses"])),
        (readme, "Of the sublane network's %d, %d %% are warned 0.5 s ahead (five-circle, `road`)" % (
            sub["crossings"], rnd(100 * sub["crossings_warned"] / sub["crossings"]))),
    ]


def run(stsim, src, work, name):
    out = os.path.join(work, name)
    args = [a if not a.endswith((".yaml", ".xml", ".sumocfg")) else os.path.join(src, a) for a in COMMANDS[name]]
    p = subprocess.run([stsim] + args + ["--out", out], cwd=work, stdout=subprocess.PIPE,
                       stderr=subprocess.PIPE, text=True, timeout=600)
    if p.returncode != 0:
        sys.exit("FAIL stsim %s: exit %d\n%s" % (" ".join(COMMANDS[name]), p.returncode, p.stderr))
    with open(os.path.join(out, "summary.json")) as f:
        summary = json.load(f)
    validation = None
    if os.path.exists(os.path.join(out, "validation.json")):
        with open(os.path.join(out, "validation.json")) as f:
            validation = json.load(f)
    with open(os.path.join(out, "warnings.csv"), newline="") as f:
        warnings = list(csv.DictReader(f))
    with open(os.path.join(out, "conflicts.csv"), newline="") as f:
        conflicts = list(csv.DictReader(f))
    return {"summary": summary, "validation": validation, "warnings": warnings, "conflicts": conflicts}


def by_type(run, t):
    return run["summary"]["warnings"]["by_type"].get(t, 0)


def network_figures(r):
    """The junction networks' READMEs: the run's counts and its validation against SSM, each in the
    same sentences."""
    out = []
    for name, readme in NETWORK_READMES.items():
        s, v = r[name]["summary"], r[name]["validation"]
        box = {d["detector"]: d for d in v["detectors"]}["box"]
        w, c = s["warnings"], s["conflicts"]

        def types(d, keys=("rear_end", "lane_change", "crossing", "pedestrian")):
            return ", ".join("%d %s" % (d[k], k.replace("_", "-").replace("lane-change", "lane change"))
                             for k in keys if d.get(k))
        fol, pet, cp = v["following"], v["pet"], v["conflict_point"]["crossing"]

        def within(n):
            return "none" if n == 0 else "%d" % n

        def pet_text(pet):
            pc = pet["conflicts"]
            if not pet["matched"]:
                return "PETs: SSM logs %d, the box warnings %d, none on both." % (pet["ssm_pets"], pet["stsim_pets"])
            return ("PETs: %d box warnings' PETs match SSM's (of its %d), %s within 0.1 s (mean difference %.2f s, largest %.2f s); "
                    "of conflicts.csv's %d PETs, %d match SSM's encounters (of %d), %s within 0.1 s."
                    % (pet["matched"], pet["ssm_pets"], within(pet["within_tolerance"]), pet["mean_abs_error_s"],
                       pet["max_abs_error_s"], pc["conflict_pets"], pc["matched"], pc["ssm_encounters"],
                       within(pc["within_tolerance"]))
                    + " Of the %d box PETs, %d have SSM's PET position off the other vehicle's path (`pet.ssm_off_path`); "
                    "%s on both paths, %s within 0.1 s."
                    % (pet["matched"], pet["ssm_off_path"], within(pet["on_both_paths"]["matched"]),
                       within(pet["on_both_paths"]["within_tolerance"])))
        out += [
            (readme, "(box detector, %d vehicles): %d vehicle warnings%s, %d conflicts in conflicts.csv%s"
             % (s["vehicles"], w["by_kind"]["vehicle"], " (%s)" % types(w["by_type"]) if w["by_kind"]["vehicle"] else "",
                c["count"], " (%s; %s at a junction, %d outside)" % (
                    types(c["by_type"]), sum(j["count"] for j in c["by_junction"].values()), c["outside_junctions"])
                if c["count"] else "")),
            (readme, "SUMO reports %d collisions, %d warned ahead" % (s["sumo_collisions"], s["collisions_warned"])),
            (readme, "the box warnings SSM also logs a TTC for are %d of %d (precision %s); SSM's following "
             "conflicts with a minimum TTC below the ego's safe time: %d, the box detector warned of %d"
             % (box["confirmed_by_ssm"], box["warnings"],
                "n/a" if box["precision"] is None else "%.3f" % box["precision"], box["ssm_conflicts_below_safe_time"],
                box["recalled"])),
            (readme, "Following TTC is within 0.02 s of SSM's on %.2f %% of %d matched samples (of %d); the largest difference (%.2f s, `following.worst` %s)"
             % (100.0 * fol["within_fraction"], fol["matched_samples"], fol["ssm_samples"], fol["max_abs_error_s"], fol["worst"])),
            (readme, pet_text(pet)),
            (readme, "Crossing conflict points: %d matched, %s within 0.5 m of SSM's along the follower's path%s."
             % (cp["matched"], within(cp["within_tolerance"]),
                "" if not cp["matched"] else " (mean %.2f m, largest %.2f m)" % (cp["mean_abs_error_m"], cp["max_abs_error_m"]))),
        ]
        if name == "bicycles":  # the conflicts with a bicycle, counted apart
            b = c["with_bicycle"]
            out.append((readme, "%d of the %d conflicts have a bicycle in them (%s), %d of them between two bicycles"
                        % (b["count"], c["count"], types(b["by_type"]), b["between_bicycles"])))
    return out


def encounter_figures(r):
    """The junction networks' conflicts by encounter, each confirmed by SSM, by SUMO's collision or
    by SUMO's next positions (validation.json `encounter`), in one sentence per README."""
    out = []
    for name, readme in ENCOUNTER_READMES.items():
        e = r[name]["validation"]["encounter"]
        m, by = e["where_ssm_models"], e["by_encounter"]
        confirmed = lambda p: p["seen_by_ssm"] + p["collided"] + p["came_close"]
        total = sum(p["conflicts"] for p in by.values())
        outside = {k: p for k, p in by.items() if k in ("diverging", "adjacent", "pedestrian", "unknown")}
        text = ("Of conflicts.csv's %d conflicts, %d are of encounters SSM models (following, merging, crossing): "
                "SSM logged %d of them with a TTC, %d collided in SUMO and %d more came within 0.5 m at SUMO's "
                "positions (`encounter.where_ssm_models`)" % (total, m["conflicts"], m["seen_by_ssm"], m["collided"],
                                                              m["came_close"]))
        if outside:
            text += "; of the rest, %s" % ", ".join(
                "%d of %d %s" % (confirmed(p), p["conflicts"], k) for k, p in sorted(outside.items()))
            text += " were confirmed the same way"
        out.append((readme, text + "."))
        pm = r[name]["validation"]["conflict_point"]["paths_meet"]
        on = pm["on_both_paths"]
        text = ("Where the paths meet (conflicts.csv's `paths_meet_x`, from the lanes) against SSM's conflict point, "
                "like for like (`conflict_point.paths_meet`): %d conflicts of crossing or merging paths, %d of them "
                "logged by SSM at their minimum-TTC tick" % (pm["conflicts"], pm["matched"]))
        if pm["ssm_off_path"]:
            text += ", %d of these with SSM's point at a left turn's wait point, off the other's path" % pm["ssm_off_path"]
        if on["matched"]:
            text += "; of the %d on both paths, %d within 0.5 m (largest %.2f m)" % (
                on["matched"], on["within_tolerance"], on["max_abs_error_m"])
        out.append((readme, text + "."))
    return out


def figures(r):
    """[(README, text)]: each quoted figure filled with what the commands wrote."""
    main, conc, box = r["main"], r["main_concentric"], r["main_box"]
    v = main["validation"]
    ld = r["lanedrop"]["validation"]
    xpet = r["crossing"]["validation"]["pet"]
    xcp = r["crossing"]["validation"]["conflict_point"]["crossing"]
    fol = v["following"]
    det = {d["detector"]: d for d in v["detectors"]}
    n_ssm = det["box"]["ssm_conflicts_below_safe_time"]

    def ratio(d, part="confirmed_by_ssm", whole="warnings"):
        return "%.3f (%s/%s)" % (d[part] / d[whole], d[part], thousands(d[whole]))

    zones = []
    for name in ("concentric", "five", "box"):
        z = det[name]["not_seen_by_ssm_by_zone"]
        order = sorted(z, key=lambda k: -z[k])
        zones.append(name + " " + ", ".join("%s %s" % (k, thousands(z[k])) for k in order))
    five_rows = main["warnings"]
    conf_rear = sum(1 for w in five_rows if w["type"] == "rear_end" and w["verdict"] == "confirmed")
    conf_prox = sum(1 for w in five_rows if w["type"] == "proximity" and w["verdict"] == "confirmed")

    def detector_row(run):
        s = run["summary"]["warnings"]
        return (by_type(run, "rear_end"), by_type(run, "lane_change"), by_type(run, "proximity"),
                s["by_kind"]["vehicle"])

    # the main job's conflicts: one row per pair and encounter, and summary.json counts the rows
    rows = main["conflicts"]
    distinct = {(min(c["first"], c["second"]), max(c["first"], c["second"]), c["begin"]) for c in rows}
    cs = main["summary"]["conflicts"]
    if len(distinct) != len(rows) or cs["count"] != len(rows):
        sys.exit("FAIL main job: conflicts.count %d, %d rows of conflicts.csv, %d distinct" % (cs["count"], len(rows), len(distinct)))
    ms = main["summary"]

    f_re, f_lc, f_px, f_veh = detector_row(main)
    c_re, c_lc, c_px, c_veh = detector_row(conc)
    b_re, b_lc, _, _ = detector_row(box)
    vehicles = main["summary"]["vehicles"]

    def points(cp):
        return "%d, %d, %d" % (cp["box_episodes"], cp["ssm_following"], cp["matched"])

    def agreement(a, unit="m"):
        return "%.2f %%** (max %.3f %s, mean %.3f %s)" % (100.0 * a["within_fraction"], a["max_abs_error_" + unit], unit,
                                                        a["mean_abs_error_" + unit], unit)

    def ramp_row(name):
        d = {x["detector"]: x for x in r[name]["validation"]["detectors"]}["box"]
        return "%d/%d (%.3f)" % (d["conflicts"]["confirmed_by_ssm"], d["conflicts"]["warnings"], d["conflicts"]["precision"])

    def ramp_recall(name):
        d = {x["detector"]: x for x in r[name]["validation"]["detectors"]}["box"]
        return "%d/%d" % (d["recalled"], d["ssm_conflicts_below_safe_time"])

    def ramp_conflicts(name):
        c = r[name]["summary"]["conflicts"]
        t = c["by_type"]
        return "%d (rear-end %d, lane change %d, crossing %d)" % (c["count"], t["rear_end"], t["lane_change"], t["crossing"])
    ramps = ("onramp_short", "onramp_long", "ramp_lanedrop")
    ramp_figures = [
        ("networks/onramp/README.md", "| conflicts (conflicts.csv) | %s | %s |" % tuple(ramp_conflicts(n) for n in ramps[:2])),
        ("networks/onramp/README.md", "| box detector: its conflicts SSM also saw (precision) | %s | %s |" % tuple(ramp_row(n) for n in ramps[:2])),
        ("networks/onramp/README.md", "| box detector: SSM's conflicts below the safe time it warned of (recall) | %s | %s |"
         % tuple(ramp_recall(n) for n in ramps[:2])),
        ("networks/lanedrop/README.md", "%s conflicts; the box detector's conflicts SSM also saw %s, SSM's conflicts below the safe time it warned of %s."
         % (ramp_conflicts("ramp_lanedrop"), ramp_row("ramp_lanedrop"), ramp_recall("ramp_lanedrop"))),
    ]

    cp, lcp, lfol = v["conflict_point"], ld["conflict_point"], ld["following"]
    raw = cp["without_moving_on"]
    return ramp_figures + network_figures(r) + encounter_figures(r) + [
        ("cosim/README.md", "| PET on the pairs both have (SSM: merging and crossing encounters; ours: `lane_change`, `crossing`) | SSM %d, box %d: %s |"
         % (v["pet"]["ssm_pets"], v["pet"]["stsim_pets"], "none on both sides" if v["pet"]["matched"] == 0 else "%d on both" % v["pet"]["matched"])),
        ("cosim/README.md", "| conflict point: box episodes with one, `rear_end` ones SSM has as following at their minimum-TTC tick, with the same TTC | %s |"
         % points(cp)),
        ("cosim/README.md", "| conflict point within 0.5 m of SSM's (moved on to the contact) | **%s |" % agreement(cp)),
        ("cosim/README.md", "| same with SSM's point as it is | %.1f %% (%d of %d) |"
         % (100.0 * raw["within_tolerance"] / raw["matched"], raw["within_tolerance"], raw["matched"])),
        ("cosim/README.md", "| following samples matched by a box TTC, within 0.02 s of SSM's | %s of %s, %.2f %% |"
         % (thousands(lfol["matched_samples"]), thousands(lfol["ssm_samples"]), 100.0 * lfol["within_fraction"])),
        ("cosim/README.md", "| PET | SSM %d, box %d: %s |"
         % (ld["pet"]["ssm_pets"], ld["pet"]["stsim_pets"], "none on both sides" if ld["pet"]["matched"] == 0 else "%d on both" % ld["pet"]["matched"])),
        ("cosim/README.md", "| conflict point: box episodes with one, `rear_end` ones SSM has as following, with the same TTC | %s |" % points(lcp)),
        ("cosim/README.md", "| same TTC: the distance along the leader's path within 0.5 m | **%s |" % agreement(lcp["along_leader_path"])),
        ("cosim/README.md", "| same TTC: the distance within 0.5 m | %s |" % agreement(lcp).replace("**", "")),
        ("cosim/README.md", "| whatever the TTC: the distance within 0.5 m | %s |" % agreement(lcp["whatever_the_ttc"]).replace("**", "")),
        ("cosim/README.md", "so only %d of its %d following samples at our minimum-TTC ticks see the approach we see"
         % (lcp["matched"], lcp["ssm_following"])),
        ("cosim/README.md", "| PETs: SSM's (crossing encounters), the box detector's (its `crossing` episodes), on both | %d, %d, %d |"
         % (xpet["ssm_pets"], xpet["stsim_pets"], xpet["matched"])),
        ("cosim/README.md", "| PET within 0.1 s of SSM's | **%.2f %%** (max %s s, mean %s s) |"
         % (100.0 * xpet["within_fraction"], sci(xpet["max_abs_error_s"]), sci(xpet["mean_abs_error_s"]))),
        ("cosim/README.md", "episode (TTC below the safe time) or a conflict (TTC below TTC*), hence %d of %d and %d of %d."
         % (xpet["stsim_pets"], xpet["ssm_pets"], xpet["conflicts"]["conflict_pets"], xpet["conflicts"]["ssm_encounters"])),
        ("cosim/README.md", "| the analyst's PETs: SSM's encounters (each pair once), conflicts.csv's conflicts with a PET, on both (`pet.conflicts`) | %d, %d, %d |"
         % (xpet["conflicts"]["ssm_encounters"], xpet["conflicts"]["conflict_pets"], xpet["conflicts"]["matched"])),
        ("cosim/README.md", "| conflicts.csv's PET within 0.1 s of SSM's | **%.2f %%** (max %s s) |"
         % (100.0 * xpet["conflicts"]["within_fraction"], sci(xpet["conflicts"]["max_abs_error_s"]))),
        ("cosim/README.md", "| conflict points: box `lane_change`/`crossing` episodes with one, SSM crossing samples with a leader at their minimum-TTC tick | %d, %d |"
         % (xcp["box_episodes"], xcp["matched"])),
        ("cosim/README.md", "| along the follower's path within 0.5 m of SSM's (where the follower enters the conflict area) | **%s |"
         % agreement(xcp)),
        ("cosim/README.md", "| the distance within 0.5 m | %s |" % agreement(xcp["distance"]).replace("**", "")),
        ("README.md", "(about %d vehicles," % (round(vehicles / 10.0) * 10)),
        ("networks/motorway/README.md", "%d emergency brakings and %d rear-end collision%s in 420 s (the bodies touching; SUMO's "
         "default rule reports %d, the other %d are minGap violations with the bodies apart)"
         % (359, ms["contacts"], "" if ms["contacts"] == 1 else "s", ms["sumo_collisions"], ms["mingap_violations"])),
        ("networks/motorway/README.md", "stsim counts %d conflicts in it (SSAM's TTC* %s s, one per pair and encounter: "
         "%d rear-end, %d lane change, %d crossing; `conflicts.csv`)"
         % (cs["count"], "%g" % cs["max_ttc_s"], cs["by_type"]["rear_end"], cs["by_type"]["lane_change"],
            cs["by_type"]["crossing"])),
        ("cosim/README.md", "| following samples (SSM FOLLOWING_FOLLOWER with a TTC) | %s, of which %s matched by a box TTC |"
         % (thin(fol["ssm_samples"]), thin(fol["matched_samples"]))),
        ("cosim/README.md", "| box TTC within 0.02 s of SSM's | **%.2f %%** (max error %.3f s, mean %s s) |"
         % (100.0 * fol["within_fraction"], fol["max_abs_error_s"], sci(fol["mean_abs_error_s"]))),
        ("cosim/README.md", "| same without the one-step shift | %.1f %% (%s of %s) |"
         % (100.0 * fol["without_time_shift"]["within_tolerance"] / fol["without_time_shift"]["matched_samples"],
            thousands(fol["without_time_shift"]["within_tolerance"]),
            thousands(fol["without_time_shift"]["matched_samples"]))),
        ("cosim/README.md", "| SSM conflicts with min TTC below the ego's safe time | %d |" % n_ssm),
        ("cosim/README.md", "| recall, concentric / five-circle / box | **%s** |"
         % ", ".join("%d/%d" % (det[d]["recalled"], n_ssm) for d in ("concentric", "five", "box"))),
        ("cosim/README.md", "| precision (car-car warnings SSM also saw) | concentric %s, five %s, box %s |"
         % (ratio(det["concentric"]), ratio(det["five"]), ratio(det["box"]))),
        ("cosim/README.md", "| the conflicts alone (SSAM's types; proximity left out): recall | concentric %d/%d, five %d/%d, box %d/%d |"
         % (det["concentric"]["conflicts"]["recalled"], n_ssm, det["five"]["conflicts"]["recalled"], n_ssm,
            det["box"]["conflicts"]["recalled"], n_ssm)),
        ("cosim/README.md", "| the conflicts alone: precision | concentric %s, five %s, box %s |"
         % (ratio(det["concentric"]["conflicts"]), ratio(det["five"]["conflicts"]), ratio(det["box"]["conflicts"]))),
        ("cosim/README.md", "| warnings SSM cannot see, by zone | %s |" % "; ".join(zones)),
        ("models/highway/README.md", "| motorway/scenario.yaml (the main job) | %d + %d, proximity %s (of %s) | %d + %d, proximity %s (of %s) | %d + %d |"
         % (f_re, f_lc, thousands(f_px), thousands(f_veh), c_re, c_lc, thousands(c_px), thousands(c_veh), b_re, b_lc)),
        ("models/highway/README.md", "networks/motorway/scenario.yaml`): %d conflicts at TTC* %g s; the rear-end conflicts cluster"
         % (cs["count"], cs["max_ttc_s"])),
        ("models/highway/README.md", "Hindsight confirms %d of the five-circle's %d rear-end conflicts and %d of its %d proximity warnings."
         % (conf_rear, f_re, conf_prox, f_px)),
        ("models/highway/README.md", "conflicts is complete, %d/%d, because" % (det["five"]["recalled"], n_ssm)),
        ("models/highway/README.md", "and %d of its %d warnings are SSM's conflicts (%.3f)."
         % (det["box"]["confirmed_by_ssm"], det["box"]["warnings"], det["box"]["precision"])),
        ("models/highway/README.md", "(five-circle %d/%d = %.3f) but recalls fewer (%d/%d)"
         % (det["five"]["conflicts"]["confirmed_by_ssm"], det["five"]["conflicts"]["warnings"],
            det["five"]["conflicts"]["precision"], det["five"]["conflicts"]["recalled"], n_ssm)),
    ]


def main():
    args = sys.argv[1:]
    keep, show, long, slow = None, "--print" in args, "--long" in args, "--slow" in args
    for flag in ("--print", "--long", "--slow"):
        if flag in args:
            args.remove(flag)
    if "--keep" in args:
        i = args.index("--keep")
        keep = args[i + 1]
        del args[i:i + 2]
    stsim, src = os.path.abspath(args[0]), os.path.abspath(args[1])
    work = keep or tempfile.mkdtemp(prefix="stsim_doc_figures_")
    os.makedirs(work, exist_ok=True)
    try:
        if slow:
            batches = {name: run_batch(stsim, src, work, name) for name in SLOW_BATCHES}
            checks = brake_figures(batches) + real_figures(batches)
        elif long:
            batches = {name: run_batch(stsim, src, work, name) for name in BATCHES}
            checks = long_figures(batches) + demand_figures(batches) + accel_lane_figures(batches)
        else:
            checks = figures({name: run(stsim, src, work, name) for name in COMMANDS})
        fails = []
        for readme, text in checks:
            if show:
                print("%s: %s" % (readme, text))
                continue
            with open(os.path.join(src, readme)) as f:
                # a figure may wrap: every run of white space counts as one space
                body = " ".join(f.read().split())
            if " ".join(text.split()) not in body:
                fails.append("%s should read: %s" % (readme, text))
        for msg in fails:
            print("FAIL " + msg)
        if fails:
            print("(the figures come from: %s)" % "; ".join(
                ["stsim batch %s with fixed %s" % b[:2] for b in (SLOW_BATCHES if slow else BATCHES).values()]
                if long or slow else
                ["stsim " + " ".join(c) for c in COMMANDS.values()]))
        return 1 if fails else 0
    finally:
        if not keep:
            shutil.rmtree(work, ignore_errors=True)


if __name__ == "__main__":
    sys.exit(main())
