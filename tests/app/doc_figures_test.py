#!/usr/bin/env python3
"""The figures the READMEs quote cannot drift from what stsim gives.

Each quoted figure below is a template over what a named command writes (the command the README
itself names). The test runs each command once, fills the templates with the values it wrote and
checks that every README holds the filled text verbatim: a change that moves a figure fails here,
naming the file, the text it should now read and the command that makes it.

  usage: doc_figures_test.py STSIM SOURCE_DIR [--keep DIR] [--print]
  --print prints the filled texts instead of checking (to update a README by hand).

Needs SUMO (the commands are live highway runs, about 15 s each).
"""
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
}


def run(stsim, src, work, name):
    out = os.path.join(work, name)
    args = [a if not a.endswith((".yaml", ".xml")) else os.path.join(src, a) for a in COMMANDS[name]]
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
    return {"summary": summary, "validation": validation, "warnings": warnings}


def by_type(run, t):
    return run["summary"]["warnings"]["by_type"].get(t, 0)


def figures(r):
    """[(README, text)]: each quoted figure filled with what the commands wrote."""
    main, conc, box = r["main"], r["main_concentric"], r["main_box"]
    v = main["validation"]
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

    f_re, f_lc, f_px, f_veh = detector_row(main)
    c_re, c_lc, c_px, c_veh = detector_row(conc)
    b_re, b_lc, _, _ = detector_row(box)
    vehicles = main["summary"]["vehicles"]
    return [
        ("README.md", "(about %d vehicles," % (round(vehicles / 10.0) * 10)),
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
    keep, show = None, "--print" in args
    if show:
        args.remove("--print")
    if "--keep" in args:
        i = args.index("--keep")
        keep = args[i + 1]
        del args[i:i + 2]
    stsim, src = os.path.abspath(args[0]), os.path.abspath(args[1])
    work = keep or tempfile.mkdtemp(prefix="stsim_doc_figures_")
    os.makedirs(work, exist_ok=True)
    try:
        results = {name: run(stsim, src, work, name) for name in COMMANDS}
        fails = []
        for readme, text in figures(results):
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
            print("(the figures come from: %s)" % "; ".join("stsim " + " ".join(c) for c in COMMANDS.values()))
        return 1 if fails else 0
    finally:
        if not keep:
            shutil.rmtree(work, ignore_errors=True)


if __name__ == "__main__":
    sys.exit(main())
