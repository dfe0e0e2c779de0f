"""One conversion from SUMO's records, whatever the path: the records of
tests/data/highway/one_conversion.csv given to step_sumo (with the vTypes as SUMO reports them
through TraCI) and the same records as an FCD trace read by stsim.FcdReader with their vType file
give the same warnings, float for float (the C++ side, live backend against FcdReader state by
state: tests/cosim/one_conversion_test.cpp)."""
import csv
import itertools

import pytest

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


def test_a_red_light_through_step_sumo_is_the_stop_distance_of_step():
    """SUMO's next light (next_signal, next_signal_distance) goes through the same conversion as the
    live coupling: red 20 m ahead is stop_distance 20 in our convention, and the car behind is
    warned of the leader braking to its line (at equal speeds, no warning without the light)."""
    def cars(sumo, light):
        lead = {"id": "lead", "speed": 10.0, "length": 4.0, "width": 1.8}
        follow = {"id": "follow", "speed": 10.0, "length": 4.0, "width": 1.8}
        if sumo:
            lead.update(x=5.0 + 2.0, y=0.0, angle=90.0)  # front bumper
            follow.update(x=2.0, y=0.0, angle=90.0)
            if light:
                lead.update(next_signal=light, next_signal_distance=20.0)
        else:
            lead.update(x=5.0, y=0.0, heading=0.0, stop_distance=20.0 if light == "r" else None)
            follow.update(x=0.0, y=0.0, heading=0.0)
        return [lead, follow]

    def alerts(sumo, light):
        m = stsim.Monitor(detector="box", check_road=False)
        (m.step_sumo if sumo else m.step)(0.0, cars(sumo, light))
        return [(a.vehicle, a.foe, a.ttc) for a in m.alerts()]

    red = alerts(True, "r")
    assert red == alerts(False, "r")
    assert sorted((v, f) for v, f, _ in red) == [(0, "follow"), (1, "lead")]  # each warns of the other
    for _, _, ttc in red:
        assert abs(ttc - (1.0 / 1.25) ** 0.5) < 1e-6  # 10 t - 1.25 t^2 closes the 1 m gap
    assert alerts(True, "G") == alerts(True, None) == alerts(False, None) == []
    for bad, match in (({"next_signal": "x", "next_signal_distance": 1.0}, "link states"),
                       ({"next_signal": "r"}, "next_signal_distance"),
                       ({"stop_distance": 5.0}, "stop_distance")):
        v = cars(True, None)
        v[0].update(bad)
        with pytest.raises(ValueError, match=match):
            stsim.Monitor().step_sumo(0.0, v)
    with pytest.raises(ValueError, match="step_sumo"):
        stsim.Monitor().step(0.0, [{"id": "a", "x": 0.0, "y": 0.0, "heading": 0.0, "speed": 1.0, "next_signal": "r"}])
