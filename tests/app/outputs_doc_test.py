#!/usr/bin/env python3
"""docs/outputs.md cannot drift from what stsim writes.

Runs every command that writes a CSV or JSON file on a small input (pool, arm and its stopping
study, arm serve and arm stream, a highway replay; with SUMO a live highway run with
--validate-ssm and a highway batch), reads the header of every CSV and the keys of every JSON
file they wrote (and the data an HTML page inlines), and checks both ways against the file's table in docs/outputs.md:

- every column (key) written is documented;
- every documented column (key) is written, unless its meaning begins with "Only" (written in
  some runs only); one beginning with "Live runs" is required when SUMO is there.

A documented name may hold placeholders, <name>: one listed under "Placeholders" in the doc
stands for one of its listed values; <sweep key> and <seed key> for the batch experiment's;
<metric> for any documented key of the batch command's summary.json (and ssm.<key> of
validation.json), in the form the batch flattens them to; any other for any text.

JSON keys are written as paths: a.b for key b inside object a, a[] for the elements of array a
(a[].b for a key of its objects).

  usage: outputs_doc_test.py STSIM SOURCE_DIR [--with-sumo] [--keep DIR] [--dump]
  --dump prints what the runs wrote (file: names) instead of checking.
"""
import json
import os
import re
import shutil
import socket
import subprocess
import sys
import tempfile
import time

# the sections of docs/outputs.md and the files that fill them, relative to the work folder
FILES = {
    "pool/events.csv": ["pool/events.csv"],
    "pool/summary.json": ["pool/summary.json"],
    "arm/warnings.csv": ["arm/warnings.csv"],
    "arm/summary.json": ["arm/summary.json"],
    "arm/replay.html": ["arm/replay.html"],
    "arm/sensors.csv": ["sensors.csv"],
    "arm/stopping_study.csv": ["study/stopping_study.csv"],
    "arm serve/verdicts.csv": ["serve/verdicts.csv"],
    "arm serve/connections.csv": ["serve/connections.csv"],
    "arm stream/stream_verdicts.csv": ["stream/stream_verdicts.csv"],
    "highway/warnings.csv": ["replay/warnings.csv", "live/warnings.csv"],
    "highway/conflicts.csv": ["replay/conflicts.csv", "live/conflicts.csv"],
    "highway/events.csv": ["replay/events.csv", "live/events.csv"],
    "highway/trajectories.csv": ["replay/trajectories.csv"],
    "highway/summary.json": ["replay/summary.json", "live/summary.json"],
    "highway/collisions.csv": ["live/collisions.csv"],
    "highway/collision_warnings.csv": ["live/collision_warnings.csv"],
    "highway/exposure.csv": ["live/exposure.csv"],
    "highway/validation.json": ["live/validation.json"],
    "batch/runs.csv": ["batch/runs.csv"],
    "batch/summary.csv": ["batch/summary.csv"],
    "batch/paired.csv": ["batch/paired.csv"],
    "batch/hindsight.csv": ["batch/hindsight.csv"],
    "batch/conflicts.csv": ["batch/conflicts.csv"],
    "batch/conflicts_compared.csv": ["batch/conflicts_compared.csv"],
}
LIVE = {"highway/collisions.csv", "highway/collision_warnings.csv", "highway/exposure.csv", "highway/validation.json", "batch/runs.csv",
        "batch/summary.csv", "batch/paired.csv", "batch/hindsight.csv", "batch/conflicts.csv",
        "batch/conflicts_compared.csv"}
SWEEP = ["detector"]  # the batch experiment below
SEED = "seed"


def run(cmd, cwd, timeout=300):
    p = subprocess.run(cmd, cwd=cwd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, timeout=timeout)
    if p.returncode != 0:
        sys.exit("FAIL %s: exit %d\n%s" % (" ".join(cmd), p.returncode, p.stderr))
    return p


def run_all(stsim, src, work, have_sumo):
    scen = os.path.join(src, "models/arm/scenarios/two_pandas.yaml")
    run([stsim, "pool", os.path.join(src, "models/pool/scenarios/break.yaml"), "--out", "pool"], work)
    run([stsim, "arm", scen, "--out", "arm", "--record-trace", "sensors.csv"], work)
    run([stsim, "arm", "--study", "stopping", "--courses", "2", "--shipped", os.path.join(src, "models/arm/scenarios"),
         "--out", "study"], work)
    # the service and a client streaming the recorded trace to it
    serve = subprocess.Popen([stsim, "arm", "serve", scen, "--listen", "127.0.0.1:0", "--out", "serve"], cwd=work,
                             stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    try:
        port = None
        deadline = time.time() + 30
        while port is None and time.time() < deadline:
            line = serve.stdout.readline()
            m = re.search(r"listening on 127\.0\.0\.1:(\d+)", line)
            if m:
                port = m.group(1)
            elif not line and serve.poll() is not None:
                break
        if port is None:
            sys.exit("FAIL arm serve did not start: " + serve.stderr.read())
        run([stsim, "arm", "stream", "--connect", "127.0.0.1:" + port, "sensors.csv", "--out", "stream"], work)
    finally:
        serve.terminate()
        serve.wait(timeout=30)
    fcd = os.path.join(src, "tests/data/highway/motorway_merge.fcd.xml")
    net = os.path.join(src, "networks/motorway/motorway.net.xml")
    run([stsim, "highway", "--fcd", fcd, "--net", net, "--out", "replay", "--trajectories"], work)
    if not have_sumo:
        return
    run([stsim, "highway", os.path.join(src, "networks/motorway/scenario.yaml"), "--end", "30", "--no-map",
         "--validate-ssm", "--out", "live"], work)
    with open(os.path.join(work, "batch.yaml"), "w") as f:
        f.write("name: outputs\ncommand: highway\nbase: %s\nsweep:\n  detector: [five, box]\n"
                "fixed:\n  end: 20\n  action: none\n  validate_ssm: true\nwarmup: 5\nseeds: 1\n"
                % os.path.join(src, "networks/sublane/scenario.yaml"))
    run([stsim, "batch", "batch.yaml", "--jobs", "1", "--no-plots", "--out", "batch"], work)


# --- what was written ---------------------------------------------------------------------------

def csv_header(path):
    import csv
    with open(path, newline="") as f:
        return next(csv.reader(f), [])


def json_paths(value, prefix=""):
    """The key paths of a JSON document: a.b, a[] for an array's elements, a[].b."""
    out = []
    if isinstance(value, dict):
        if not value and prefix:
            out.append(prefix)
        for k, v in value.items():
            out += json_paths(v, prefix + "." + k if prefix else k)
    elif isinstance(value, list):
        p = prefix + "[]"
        if not value:
            out.append(p)
        for v in value:
            out += json_paths(v, p)
    else:
        out.append(prefix)
    return list(dict.fromkeys(out))


def written(path):
    if path.endswith(".csv"):
        return csv_header(path)
    if path.endswith(".html"):
        # a page's data: the JSON object it inlines as `const D = {...};` (one line)
        with open(path) as f:
            m = re.search(r"^const D = (.*);$", f.read(), re.M)
        return json_paths(json.loads(m.group(1))) if m else ["(no const D = ... in the page)"]
    with open(path) as f:
        return json_paths(json.load(f))


# --- what is documented -------------------------------------------------------------------------

def parse_doc(path):
    """{section: [(name, meaning)]}, {placeholder: [values]}"""
    sections, placeholders = {}, {}
    section = None
    with open(path) as f:
        for line in f:
            m = re.match(r"^#{2,4} `([^`]+)`", line)
            if m:
                section = m.group(1)
                sections.setdefault(section, [])
                continue
            if line.startswith("#"):
                section = None
            m = re.match(r"^- `(<[^>]+>)`: (.*)$", line)
            if m:
                placeholders[m.group(1)] = re.findall(r"`([^`]+)`", m.group(2))
                continue
            if section is None or not line.startswith("|"):
                continue
            cells = [c.strip() for c in line.strip().strip("|").split("|")]
            m = re.match(r"^`([^`]+)`$", cells[0])
            if m and len(cells) >= 3:
                sections[section].append((m.group(1), cells[-1]))
    return sections, placeholders


def pattern(name, placeholders, json_key, metrics=None):
    """A regex for a documented name."""
    seg = r"[^.\[\]]+" if json_key else r".+?"
    out = ""
    for part in re.split(r"(<[^>]+>)", name):
        if not part:
            continue
        if part.startswith("<"):
            if part == "<sweep key>":
                out += "(?:%s)" % "|".join(map(re.escape, SWEEP))
            elif part == "<seed key>":
                out += re.escape(SEED)
            elif part == "<metric>" and metrics is not None:
                out += "(?:%s)" % "|".join(metrics)
            elif part in placeholders:
                out += "(?:%s)" % "|".join(map(re.escape, placeholders[part]))
            else:
                out += seg
        else:
            out += re.escape(part)
    return out


def main():
    args = sys.argv[1:]
    keep = None
    have_sumo = "--with-sumo" in args  # stsim built with SUMO (cosim/): the live runs too
    dump = "--dump" in args
    for flag in ("--dump", "--with-sumo"):
        if flag in args:
            args.remove(flag)
    if "--keep" in args:
        i = args.index("--keep")
        keep = args[i + 1]
        del args[i:i + 2]
    stsim, src = os.path.abspath(args[0]), os.path.abspath(args[1])
    work = keep or tempfile.mkdtemp(prefix="stsim_outputs_")
    os.makedirs(work, exist_ok=True)
    try:
        run_all(stsim, src, work, have_sumo)
        if dump:
            for section, files in FILES.items():
                for f in files:
                    p = os.path.join(work, f)
                    if os.path.exists(p):
                        print("%s (%s): %s" % (section, f, " ".join(written(p))))
            return 0
        return check(src, work, have_sumo)
    finally:
        if not keep:
            shutil.rmtree(work, ignore_errors=True)


def check(src, work, have_sumo):
    sections, placeholders = parse_doc(os.path.join(src, "docs/outputs.md"))
    fails = []
    # the batch's metrics: the documented keys of the command's summary.json, flattened as the
    # batch flattens them (an array's objects by their detector or name), validation.json's as ssm.*
    def flat(section, prefix=""):
        out = []
        for name, _ in sections.get(section, []):
            p = pattern(name, placeholders, True).replace(r"\[\]", r"\.[^.]+")
            out.append(re.escape(prefix) + p if prefix else p)
            # a documented object of figures (lead_s: {min, median, p90}) may be null: one column
            out.append(re.escape(prefix) + pattern(name.rsplit(".", 1)[0], placeholders, True)
                       if "." in name else p)
        return out
    metrics = flat("highway/summary.json") + flat("highway/validation.json", "ssm.")
    # the batch's own figures of a highway run (exposure.*, counted.*, rate.*), documented in runs.csv's table
    metrics += [pattern(n, placeholders, True) for n, _ in sections.get("batch/runs.csv", [])
                if n.split(".")[0] in ("exposure", "counted", "rate")]
    # ... and hindsight's figures after a warm-up, under summary.json's names (runs.csv's after_warmup.<metric>)
    metrics += [re.escape("after_warmup.") + m for m in flat("highway/summary.json")]
    for section, files in FILES.items():
        if section not in sections:
            fails.append("%s: no table in docs/outputs.md" % section)
            continue
        docs = sections[section]
        json_key = section.endswith((".json", ".html"))
        pats = [(n, m, re.compile("^%s$" % pattern(n, placeholders, json_key, metrics))) for n, m in docs]
        seen = []
        for f in files:
            p = os.path.join(work, f)
            if not os.path.exists(p):
                if section in LIVE and not have_sumo:
                    continue
                fails.append("%s: %s was not written" % (section, f))
                continue
            names = written(p)
            seen += names
            for n in names:
                # a JSON object written as null (nothing to count) stands for its documented keys
                ok = any(r.match(n) for _, _, r in pats) or \
                    (json_key and any(d.startswith(n + ".") or d.startswith(n + "[]") for d, _, _ in pats))
                if not ok:
                    fails.append("%s: %s writes '%s', not in docs/outputs.md" % (section, f, n))
        if not seen:
            continue
        for n, meaning, r in pats:
            if meaning.startswith("Only"):
                continue
            if meaning.startswith("Live runs") and not have_sumo:
                continue
            present = any(r.match(s) for s in seen) or \
                (json_key and any(n.startswith(s + ".") for s in seen))
            if not present:
                fails.append("%s: docs/outputs.md documents '%s', which no run wrote" % (section, n))
    for f in fails:
        print("FAIL " + f)
    checked = sum(1 for s in FILES if s in sections)
    print("%d files checked against docs/outputs.md, %d problems%s" %
          (checked, len(fails), "" if have_sumo else " (no SUMO: live highway and batch files skipped)"))
    return 1 if fails else 0


if __name__ == "__main__":
    sys.exit(main())
