"""One conversion from SUMO's records, whatever the path: the records of
tests/data/highway/one_conversion.csv given to step_sumo (with the vTypes as SUMO reports them
through TraCI) and the same records as an FCD trace read by stsim.FcdReader with their vType file
give the same warnings, float for float (the C++ side, live backend against FcdReader state by
state: tests/cosim/one_conversion_test.cpp)."""
import csv
import itertools

import stsim
from conftest import DATA

# traci.vehicletype's answers for one_conversion.rou.xml (SUMO 1.15: the attributes a vType leaves
# out are its vClass's defaults; mass is the <param>, absent where none): the C++ test checks the
# same file against a live SUMO
SUMO_TYPES = {
    "car": {"vehicle_class": "passenger", "length": 4.5, "width": 1.8, "decel": 4.5, "mass": 1300.0},
    "anon": {"vehicle_class": "passenger", "length": 4.3, "width": 1.8, "decel": 4.5},
    "trailer": {"vehicle_class": "trailer", "length": 16.5, "width": 2.55, "decel": 4.0, "mass": 30000.0},
    "bike": {"vehicle_class": "bicycle", "length": 1.6, "width": 0.65, "decel": 3.0},
}


def records():
    with open(DATA / "one_conversion.csv", newline="") as f:
        return list(csv.DictReader(f))


def write_fcd(rows, path):
    with open(path, "w") as f:
        f.write("<fcd-export>\n")
        for t, group in itertools.groupby(rows, key=lambda r: r["time"]):
            f.write(f'  <timestep time="{t}">\n')
            for r in group:
                f.write(f'    <vehicle id="{r["id"]}" x="{r["x"]}" y="{r["y"]}" angle="{r["angle"]}" type="{r["type"]}" '
                        f'speed="{r["speed"]}" posLat="{r["pos_lat"]}" lane="{r["lane"]}" signals="{r["signals"]}" '
                        f'acceleration="{r["acceleration"]}"/>\n')
            f.write("  </timestep>\n")
        f.write("</fcd-export>\n")


def finished(m, frames):
    out = []
    last = 0.0
    for t, vehicles, step in frames:
        step(m, t, vehicles)
        out += m.take_finished()
        last = t
    m.finish(last)
    out += m.take_finished()
    return [(w.ego, w.foe, w.kind, w.zone, w.begin, w.end, w.min_ttc, w.min_ttc_time, w.safe_time, w.open) for w in out]


def test_step_sumo_and_the_fcd_reader_give_the_same_warnings(tmp_path):
    rows = records()
    net = DATA / "lanedrop.net.xml"
    live = []
    for t, group in itertools.groupby(rows, key=lambda r: r["time"]):
        vehicles = []
        for r in group:
            v = {"id": r["id"], "lane": r["lane"], "signals": int(r["signals"])}
            for k in ("x", "y", "angle", "speed", "lateral_speed", "acceleration"):
                v[k] = float(r[k])
            v.update(SUMO_TYPES[r["type"]])
            vehicles.append(v)
        live.append((float(t), vehicles, lambda m, t, v: m.step_sumo(t, v)))
    fcd = tmp_path / "one_conversion.fcd.xml"
    write_fcd(rows, fcd)
    replay = [(t, v, lambda m, t, v: m.step(t, v))
              for t, v in stsim.FcdReader(fcd, DATA / "one_conversion.rou.xml", net)]
    assert [t for t, _, _ in live] == [t for t, _, _ in replay]
    for detector, motion, least in (("five", "velocity", 7), ("box", "acceleration", 2)):
        a = finished(stsim.Monitor(str(net), detector=detector, motion=motion), live)
        b = finished(stsim.Monitor(str(net), detector=detector, motion=motion), replay)
        assert len(a) >= least
        assert a == b
