#!/usr/bin/env python3
"""The junction networks (actuated, bicycles) against SUMO's own record of the same run.

networks/actuated: no crossing warning with a car that then stood at its red. The light's program
is actuated, so its states come from SUMO (SaveTLSStates) rather than from the program; each car's
link is the first signalised internal lane SUMO's FCD has it on after the warning. A car moving
when warned that stood still on that link's approach lane within 8 s while the link showed red or
yellow was predicted through its red.

networks/bicycles: bicycles keep their class and their vType's body (1.75 m x 0.7 m, neither
SUMO's nor stsim's default) in conflicts.csv; and summary.json's conflicts.with_bicycle, and the
console's "with a bicycle" count, equal a recount of conflicts.csv's rows whose vehicles the route
file makes bicycles (a flow of a vType of vClass bicycle: its vehicles are "<flow>.<n>").

  usage: junction_networks_test.py STSIM SOURCE_DIR
Needs SUMO (two live runs, about 10 s).
"""
import bisect
import collections
import csv
import json
import os
import shutil
import subprocess
import sys
import tempfile
import xml.etree.ElementTree as ET


def run(stsim, src, work, net, extra_sumo):
    d = os.path.join(work, net)
    os.makedirs(d)
    scen = os.path.join(src, "networks", net, "scenario.yaml")
    with open(scen) as f:
        text = "".join(l for l in f if not l.startswith(("sumocfg:", "out:")))
    args = ", ".join("'%s'" % a for a in extra_sumo(d))
    with open(os.path.join(d, "run.yaml"), "w") as f:
        f.write(text + "sumocfg: %s\nsumo_args: [%s]\n" % (os.path.join(src, "networks", net, net + ".sumocfg"), args))
    p = subprocess.run([stsim, "highway", os.path.join(d, "run.yaml"), "--no-map", "--out", os.path.join(d, "out")],
                       cwd=d, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, timeout=300)
    if p.returncode != 0:
        sys.exit("FAIL stsim highway %s: exit %d\n%s" % (net, p.returncode, p.stderr))
    with open(os.path.join(d, "stdout.txt"), "w") as f:
        f.write(p.stdout)
    return d


def actuated(stsim, src, work):
    def sumo(d):
        with open(os.path.join(d, "tls.add.xml"), "w") as f:
            f.write('<additional><timedEvent type="SaveTLSStates" source="C" dest="%s"/></additional>\n'
                    % os.path.join(d, "tls.xml"))
        return ["--additional-files", os.path.join(d, "tls.add.xml"), "--fcd-output", os.path.join(d, "fcd.xml"),
                "--fcd-output.attributes", "speed,lane"]
    d = run(stsim, src, work, "actuated", sumo)
    net = ET.parse(os.path.join(src, "networks/actuated/actuated.net.xml")).getroot()
    # internal lane -> (light, link index, approach lane)
    link = {c.get("via"): (c.get("tl"), int(c.get("linkIndex")), "%s_%s" % (c.get("from"), c.get("fromLane")))
            for c in net.iter("connection") if c.get("tl") and c.get("via")}
    states = collections.defaultdict(list)
    for _, el in ET.iterparse(os.path.join(d, "tls.xml")):
        if el.tag == "tlsState":
            states[el.get("id")].append((float(el.get("time")), el.get("state")))
    times = {k: [t for t, _ in v] for k, v in states.items()}

    def state(tl, i, t):
        return states[tl][max(bisect.bisect_right(times[tl], t + 1e-6) - 1, 0)][1][i]
    trace = collections.defaultdict(list)  # id -> [(t, speed, lane)]
    for _, el in ET.iterparse(os.path.join(d, "fcd.xml")):
        if el.tag == "timestep":
            t = float(el.get("time"))
            for v in el:
                if v.tag == "vehicle":
                    trace[v.get("id")].append((t, float(v.get("speed")), v.get("lane")))
            el.clear()

    def stood_at_red(vid, t):
        """moving at t, then standing on its light's approach lane within 8 s at red or yellow"""
        s = trace[vid]
        now = [x for x in s if abs(x[0] - t) < 0.05]
        if not now or now[0][1] < 0.1:
            return False
        nxt = next((link[x[2]] for x in s if x[0] >= t and x[2] in link), None)
        if not nxt:
            return False
        tl, i, approach = nxt
        return any(t <= x[0] <= t + 8 and x[1] < 0.1 and x[2] == approach and state(tl, i, x[0]) in "ryY" for x in s)
    def ever_stood(vid):
        """stood on the approach lane of its next light at red or yellow"""
        for x in trace[vid]:
            if x[1] < 0.1:
                nxt = next((link[y[2]] for y in trace[vid] if y[0] >= x[0] and y[2] in link), None)
                if nxt and nxt[2] == x[2] and state(nxt[0], nxt[1], x[0]) in "ryY":
                    return True
        return False
    stood = sum(1 for vid in trace if ever_stood(vid))
    with open(os.path.join(d, "out", "warnings.csv"), newline="") as f:
        rows = [r for r in csv.DictReader(f) if r["kind"] == "vehicle" and r["type"] == "crossing"]
    bad = ["%s x %s at %s" % (r["ego"], r["foe"], r["begin"]) for r in rows
           if stood_at_red(r["ego"], float(r["begin"])) or stood_at_red(r["foe"], float(r["begin"]))]
    fails = []
    if len(rows) < 10 or stood < 50:  # the check is not vacuous: 30 crossing warnings, 108 cars at a red
        fails.append("actuated: %d crossing warnings, %d vehicles stood at a red: too few to check" % (len(rows), stood))
    if bad:
        fails.append("actuated: crossing warnings with a car that then stood at its red: " + "; ".join(bad))
    return fails


def bicycles(stsim, src, work):
    d = run(stsim, src, work, "bicycles", lambda d: [])
    fails, n = [], 0
    with open(os.path.join(d, "out", "conflicts.csv"), newline="") as f:
        for r in csv.DictReader(f):
            for side in ("first", "second"):
                if r[side].startswith("b"):  # the bicycle flows: bwe, bew, bns, bsn
                    n += 1
                    got = (r[side + "_class"], float(r[side + "_length"]), float(r[side + "_width"]))
                    if got != ("bicycle", 1.75, 0.7):
                        fails.append("bicycles: %s in conflict at %s is %s, not (bicycle, 1.75, 0.7)" % (r[side], r["begin"], got))
    if n < 10:
        fails.append("bicycles: only %d bicycles in conflicts.csv, too few to check" % n)
    return fails + bicycle_counts(src, d)


def bicycle_counts(src, d):
    """summary.json's conflicts.with_bicycle against a recount of conflicts.csv by the route file's
    bicycle flows (not by the class columns stsim wrote)."""
    routes = ET.parse(os.path.join(src, "networks/bicycles/bicycles.rou.xml")).getroot()
    bike_types = {t.get("id") for t in routes.iter("vType") if t.get("vClass") == "bicycle"}
    bike_flows = {f.get("id") for f in routes.iter("flow") if f.get("type") in bike_types}
    def bike(vehicle):
        return vehicle.rsplit(".", 1)[0] in bike_flows
    types = ["rear_end", "lane_change", "crossing", "pedestrian"]
    by_type, between = collections.Counter({t: 0 for t in types}), 0
    with open(os.path.join(d, "out", "conflicts.csv"), newline="") as f:
        for r in csv.DictReader(f):
            if bike(r["first"]) or bike(r["second"]):
                by_type[r["type"]] += 1
                between += bike(r["first"]) and bike(r["second"])
    want = {"count": sum(by_type.values()), "between_bicycles": between, "by_type": dict(by_type)}
    with open(os.path.join(d, "out", "summary.json")) as f:
        got = json.load(f)["conflicts"].get("with_bicycle")
    fails = []
    if got != want:
        fails.append("bicycles: summary.json's conflicts.with_bicycle %s, a recount of conflicts.csv %s" % (got, want))
    # the recount is not vacuous: car-bicycle and bicycle-bicycle conflicts both
    if want["count"] - between < 3 or between < 3:
        fails.append("bicycles: %d conflicts with a bicycle, %d between two: too few to check" % (want["count"], between))
    with open(os.path.join(d, "stdout.txt")) as f:
        out = f.read()
    line = "with a bicycle %d: %s, between two bicycles %d" % (
        want["count"], ", ".join("%s %d" % (t, by_type[t]) for t in types), between)
    if line not in out:
        fails.append("bicycles: the console does not say %r:\n%s" % (line, out))
    return fails


def main():
    stsim, src = os.path.abspath(sys.argv[1]), os.path.abspath(sys.argv[2])
    work = tempfile.mkdtemp(prefix="stsim_junction_networks_")
    try:
        fails = actuated(stsim, src, work) + bicycles(stsim, src, work)
    finally:
        shutil.rmtree(work, ignore_errors=True)
    for f in fails:
        print("FAIL " + f)
    return 1 if fails else 0


if __name__ == "__main__":
    sys.exit(main())
