"""SUMO's conventions (step_sumo, TraciMonitor): checked against the conversion done by hand, and
TraciMonitor over Python's libsumo against stsim's own C++ SUMO coupling on the shipped motorway,
the sublane network and SUMO's grid6, and with traffic lights and persons on foot on the signalised
intersection and its crosswalks (warnings, conflicts.csv and events.csv alike); a route given
through Python is followed through a junction."""
import csv
import json
import math
import pathlib
import sys

import pytest

import stsim
from conftest import SOURCE, run_stsim
from test_conflict_fields import as_written, cell


def test_step_sumo_is_the_documented_conversion():
    # centre = front - L/2 (cos h, sin h), h = (90 - angle) * pi / 180; SUMO's signal bit 0 is the
    # right blinker, bit 1 the left; a SUMO vClass name maps to ours
    rows_sumo, rows_ours = [], []
    cars = [("a", 0.0, 0.0, 90.0, 30.0, 0, "passenger", 4.5), ("b", 60.0, 0.4, 90.0, 10.0, 1, "trailer", 16.0),
            ("c", 20.0, 3.0, 100.0, 28.0, 2, "passenger", 4.5), ("d", 200.0, -0.5, 270.0, 25.0, 3, "coach", 12.0)]
    for vid, x, y, angle, speed, signals, vclass, length in cars:
        rows_sumo.append({"id": vid, "x": x, "y": y, "angle": angle, "speed": speed, "signals": signals,
                          "vehicle_class": vclass, "length": length, "width": 2.0})
        h = (90.0 - angle) * math.pi / 180.0
        ours = {1: 2, 2: 1, 3: 3, 0: 0}[signals]
        rows_ours.append({"id": vid, "x": x - 0.5 * length * math.cos(h), "y": y - 0.5 * length * math.sin(h),
                          "heading": h, "speed": speed, "signals": ours, "length": length, "width": 2.0,
                          "vehicle_class": {"passenger": "passenger", "trailer": "truck", "coach": "bus"}[vclass]})
    results = []
    for rows, step in ((rows_sumo, "step_sumo"), (rows_ours, "step")):
        m = stsim.Monitor(detector="box")
        for k in range(30):
            t = 0.1 * k
            moved = []
            for r in rows:
                r = dict(r)
                if step == "step":
                    r["x"] += r["speed"] * t * math.cos(r["heading"])
                    r["y"] += r["speed"] * t * math.sin(r["heading"])
                else:
                    h = (90.0 - r["angle"]) * math.pi / 180.0
                    r["x"] += r["speed"] * t * math.cos(h)
                    r["y"] += r["speed"] * t * math.sin(h)
                moved.append(r)
            getattr(m, step)(t, moved)
        m.finish(3.0)
        results.append([(w.ego, w.foe, w.kind, w.zone, w.begin, w.end, w.min_ttc, w.safe_time)
                        for w in m.take_finished()])
    assert len(results[0]) >= 2  # a closes on b
    for got, want in zip(*results):
        assert got[:4] == want[:4] and got[4:6] == want[4:6]
        assert got[6:] == pytest.approx(want[6:], rel=1e-12, abs=1e-12)  # the moved positions round apart


def episode(row):
    # (ego, foe, kind, begin) names an episode; the other cells may be None, which does not sort
    return row[0], row[1], row[2], row[4]


def libsumo_module():
    sys.path.append("/usr/share/sumo/tools")
    try:
        import libsumo
    except ImportError:
        pytest.skip("Python libsumo not installed (sumo-tools)")
    return libsumo


def traci_module():
    sys.path.append("/usr/share/sumo/tools")
    try:
        import traci
    except ImportError:
        pytest.skip("Python traci not installed (sumo-tools)")
    if not pathlib.Path("/usr/bin/sumo").exists():
        pytest.skip("sumo not installed")
    return traci


def sumo_args(cfg, end):
    # plain `sumo -c`: stsim runs a .sumocfg with the config's own seed too (SUMO's default if none)
    return ["sumo", "-c", str(cfg), "--collision.action", "warn", "--no-step-log", "true",
            "--duration-log.disable", "true", "--duration-log.statistics", "false", "--no-warnings", "true",
            "--end", str(end)]


def network_config(network):
    cfg = SOURCE / f"networks/{network}.sumocfg"
    if not cfg.exists() or (network.endswith("grid6") and not pathlib.Path("/usr/share/sumo/tools/game/grid6").exists()):
        pytest.skip(f"{cfg} or SUMO's game networks missing")
    return cfg


def cxx_warnings(stsim_binary, cfg, end, out, *options):
    """The C++ coupling's run of cfg to `end` (no action, `options` added) into `out`: its
    warnings.csv rows, every column (hindsight, the conflict record), None where the cell is empty,
    in episode order."""
    r = run_stsim(stsim_binary, "highway", cfg, "--end", end, "--action", "none", "--out", out, *options)
    if "built without SUMO support" in r.stderr:
        pytest.skip("stsim built without SUMO (-DSTSIM_WITH_SUMO=OFF)")
    assert r.returncode == 0, r.stderr
    with open(out / "warnings.csv", newline="") as f:
        return sorted((tuple(cell(c, r[c]) for c in stsim.WARNING_COLUMNS) for r in csv.DictReader(f)), key=episode)


# the motorway (trucks with a mass param, cars without), the sublane network (lateral speeds) and
# SUMO's grid6 (junctions, lanes drawn longer than their length; its turns are signalled, so the
# route changes no warning there: test_a_route_is_followed_through_a_junction checks the route);
# over libsumo (getters) and, on the motorway, over a TraCI socket (subscriptions)
@pytest.mark.parametrize("network,backend", [("motorway/motorway", "libsumo"), ("sublane/sublane", "libsumo"),
                                             ("experiments/real_networks/grid6", "libsumo"),
                                             ("motorway/motorway", "traci")])
def test_traci_monitor_equals_the_cxx_coupling(stsim_binary, tmp_path, network, backend):
    cfg = network_config(network)
    end = 200.0 if network.endswith("grid6") else 60.0  # grid6 fills slowly
    want = cxx_warnings(stsim_binary, cfg, end, tmp_path / "cxx")
    assert len(want) > 10
    assert {"confirmed", "nuisance"} <= {w[10] for w in want}

    conn = libsumo_module() if backend == "libsumo" else traci_module()
    conn.start(sumo_args(cfg, end))
    try:
        monitor = stsim.TraciMonitor(conn)  # the road from SUMO's lanes, as the coupling reads it
        assert monitor.reader.subscribe == (backend == "traci")  # the faster per backend
        dt = conn.simulation.getDeltaT()
        events = []
        while conn.simulation.getMinExpectedNumber() > 0 and conn.simulation.getTime() < end - 0.5 * dt:
            conn.simulationStep()
            monitor.step()
            events += monitor.take_events()
        monitor.finish()
        got = sorted((tuple(as_written(c, getattr(w, c)) for c in stsim.WARNING_COLUMNS)
                      for w in monitor.take_finished()), key=episode)
    finally:
        conn.close()
    assert got == want  # bit for bit
    # the near misses and crossings that happened, as events.csv lists them
    with open(tmp_path / "cxx" / "events.csv", newline="") as f:
        want_events = [(float(r["time"]), r["kind"], r["ego"], r["foe"], r["warned"] == "1",
                        float(r["lead"]) if r["lead"] else None) for r in csv.DictReader(f)]
    assert [(e.time, e.kind, e.ego, e.foe, e.warned, e.lead) for e in events] == want_events
    if network.startswith("sublane"):
        assert "crossing" in {e[1] for e in want_events}  # (its first 60 s have no near miss)
    table = stsim.warnings_table([])
    assert list(table.keys() if isinstance(table, dict) else table.columns) == list(stsim.WARNING_COLUMNS)


# the subscription reader against the getters, step by step: the motorway (mass params, departures
# every step), grid6 (routes through junctions, route indices that advance, lights) and the
# crosswalk (persons on foot, lights); over a TraCI socket
# every 8th step (a getter is a round trip there), the subscriptions live between the reads
@pytest.mark.parametrize("backend", ["libsumo", "traci"])
@pytest.mark.parametrize("network", ["motorway/motorway", "experiments/real_networks/grid6", "crosswalk/crosswalk"])
def test_the_subscription_reader_reads_what_the_getters_read(network, backend):
    cfg = network_config(network)
    conn = libsumo_module() if backend == "libsumo" else traci_module()
    end = 80.0 if backend == "traci" else 200.0
    conn.start(sumo_args(cfg, end))
    try:
        reader = stsim.TraciVehicleReader(conn, subscribe=True)
        types = {}
        reads = vehicles = route_moves = walking = signalled = 0
        last_route = {}
        step = 0
        while conn.simulation.getMinExpectedNumber() > 0 and conn.simulation.getTime() < end - 0.01:
            conn.simulationStep()
            step += 1
            if backend == "traci" and step % 8:
                continue
            got = reader.read()
            want = stsim.read_traci_vehicles(conn, types, lights=reader.lights)  # the light states read() took
            persons = stsim.read_traci_persons(conn, types)
            if persons:  # after the vehicles, as rows
                want = (want if isinstance(want, list) else [dict(zip(want, v)) for v in zip(*want.values())]) + persons
            assert got == want, f"t = {conn.simulation.getTime()}"
            rows = got if isinstance(got, list) else [dict(zip(got, v)) for v in zip(*got.values())]
            reads += 1
            vehicles += len(rows)
            for row in rows:
                walking += row["vehicle_class"] == "pedestrian"
                signalled += row.get("next_signal") is not None
                route_moves += last_route.get(row["id"], row.get("route")) != row.get("route")
                last_route[row["id"]] = row.get("route")
    finally:
        conn.close()
    assert reads >= 10 and vehicles >= (5 if network.startswith("crosswalk") else 20) * reads
    if not network.startswith("motorway"):
        assert route_moves > 10  # vehicles went from edge to edge along their routes
        assert signalled > 10  # ... facing lights
    assert (walking > 10) == network.startswith("crosswalk")  # persons on foot, read both ways


# conflicts.csv's cells as Python gives them: text, a flag, a measure worked out to 0.001, else in full
CONFLICT_TEXT = ("first", "second", "type", "encounter", "first_lane", "second_lane", "junction", "first_class", "second_class")
CONFLICT_DERIVED = ("pet", "drac", "delta_s", "dr", "max_d", "max_delta_v", "first_delta_v", "second_delta_v",
                    "conflict_angle", "post_crash_speed", "post_crash_heading", "conflict_x", "conflict_y", "paths_meet_x",
                    "paths_meet_y", "tet", "tit")


def conflict_cell(column, text):
    if column in CONFLICT_TEXT:
        return text
    if column == "open":
        return text == "1"
    return None if text == "" else float(text)


def conflict_as_written(column, value):
    if column in CONFLICT_DERIVED and value is not None and math.isfinite(value):
        return float("%.3f" % value) + 0.0  # -0.000 is written 0
    return value


# Lights, the priority rules and persons, read by TraciMonitor as the C++ coupling reads them: the
# signalised intersection (a car facing red is predicted to stop at its line; here without the
# priority rules, so that its left turners meet the oncoming traffic) and the same with crosswalks
# and persons on foot (pedestrian conflicts; the left turners giving way at their wait points),
# over libsumo and over a TraCI socket; every warning, conflict and event equal
@pytest.mark.parametrize("network,backend,priority", [("crosswalk/crosswalk", "libsumo", True),
                                                      ("crosswalk/crosswalk", "traci", True),
                                                      ("intersection/intersection", "libsumo", False)])
def test_traci_monitor_reads_lights_and_persons_as_the_cxx_coupling(stsim_binary, tmp_path, network, backend, priority):
    cfg = network_config(network)
    end = 200.0
    want = cxx_warnings(stsim_binary, cfg, end, tmp_path / "cxx", "--set", "priority_rules=%s" % str(priority).lower())
    with open(tmp_path / "cxx" / "conflicts.csv", newline="") as f:
        reader = csv.DictReader(f)
        assert tuple(reader.fieldnames) == stsim.CONFLICT_COLUMNS
        want_conflicts = sorted(tuple(conflict_cell(c, r[c]) for c in stsim.CONFLICT_COLUMNS) for r in reader)
    with open(tmp_path / "cxx" / "events.csv", newline="") as f:
        want_events = [tuple(r[c] for c in stsim.EVENT_COLUMNS) for r in csv.DictReader(f)]
    with open(tmp_path / "cxx" / "summary.json") as f:
        summary = json.load(f)
    assert len(want) > 10 and len(want_conflicts) > 3
    if network.startswith("crosswalk"):
        assert summary["persons"] > 20
        assert "pedestrian" in {c[2] for c in want_conflicts}
    # per junction: a crossing conflict's point lies in junction C's shape (SUMO's net), and so
    # does its junction; the summary counts by junction as the rows say
    at = {c: i for i, c in enumerate(stsim.CONFLICT_COLUMNS)}
    shape = junction_shape(SOURCE / f"networks/{network}.net.xml", "C")
    crossings = [c for c in want_conflicts if c[at["type"]] == "crossing" and c[at["conflict_x"]] is not None]
    assert crossings
    for c in crossings:
        assert inside((c[at["conflict_x"]], c[at["conflict_y"]]), shape) and c[at["junction"]] == "C", c
    counted = summary["conflicts"]["by_junction"]
    assert set(counted) <= {"C"} and counted["C"]["count"] == sum(c[at["junction"]] == "C" for c in want_conflicts)
    assert counted["C"]["crossing"] == sum(c[at["junction"]] == "C" and c[at["type"]] == "crossing" for c in want_conflicts)
    assert summary["conflicts"]["outside_junctions"] == sum(c[at["junction"]] == "" for c in want_conflicts)

    conn = libsumo_module() if backend == "libsumo" else traci_module()
    conn.start(sumo_args(cfg, end))
    red = 0
    try:
        monitor = stsim.TraciMonitor(conn, priority_rules=priority)
        assert monitor.reader.lights is not None and monitor.reader.persons
        dt = conn.simulation.getDeltaT()
        events, conflicts = [], []
        while conn.simulation.getMinExpectedNumber() > 0 and conn.simulation.getTime() < end - 0.5 * dt:
            conn.simulationStep()
            monitor.step()
            events += monitor.take_events()
            conflicts += monitor.take_conflicts()
            red += sum(1 for light in monitor.reader.lights.states for s in light if s == "r")
        monitor.finish()
        conflicts += monitor.take_conflicts()
        got = sorted((tuple(as_written(c, getattr(w, c)) for c in stsim.WARNING_COLUMNS)
                      for w in monitor.take_finished()), key=episode)
        counters = monitor.counters
        assert monitor.settings == stsim.Monitor(priority_rules=priority).settings  # the C++ run's
    finally:
        conn.close()
    assert red > 0
    assert counters["persons_seen"] == summary["persons"]
    assert got == want  # bit for bit
    assert sorted(tuple(conflict_as_written(c, getattr(k, c)) for c in stsim.CONFLICT_COLUMNS)
                  for k in conflicts) == want_conflicts
    table = stsim.events_table(events)
    rows = table.to_dict("list") if hasattr(table, "to_dict") else table

    def event_cell(column, text):
        if column in ("kind", "ego", "foe", "lane"):
            return text
        if column == "warned":
            return text == "1"
        return None if text == "" else float(text)

    def value(v):  # pandas gives a missing number as NaN
        return None if isinstance(v, float) and math.isnan(v) else v

    written = [tuple(value(v) for v in r) for r in zip(*(rows[c] for c in stsim.EVENT_COLUMNS))]
    assert written == [tuple(event_cell(c, t) for c, t in zip(stsim.EVENT_COLUMNS, r)) for r in want_events]

def junction_shape(net, junction):
    import xml.etree.ElementTree as ET
    for j in ET.parse(net).getroot().iter("junction"):
        if j.get("id") == junction:
            return [tuple(map(float, p.split(","))) for p in j.get("shape").split()]
    raise AssertionError(f"no junction {junction} in {net}")


def inside(p, polygon):
    """Ray casting: p in the polygon (its edges count as in, within 1 cm)."""
    x, y = p
    n, hit = len(polygon), False
    for i in range(n):
        (x1, y1), (x2, y2) = polygon[i], polygon[(i + 1) % n]
        dx, dy = x2 - x1, y2 - y1
        t = max(0.0, min(1.0, ((x - x1) * dx + (y - y1) * dy) / (dx * dx + dy * dy or 1.0)))
        if math.hypot(x1 + t * dx - x, y1 + t * dy - y) < 0.01:
            return True
        if (y1 > y) != (y2 > y) and x < x1 + (y - y1) * dx / dy:
            hit = not hit
    return hit


def test_tables_have_the_files_columns():
    # every table of the module has its CSV file's columns, in order, and each record has each
    for make, columns in ((stsim.warnings_table, stsim.WARNING_COLUMNS), (stsim.conflicts_table, stsim.CONFLICT_COLUMNS),
                          (stsim.events_table, stsim.EVENT_COLUMNS), (stsim.alerts_table, stsim.ALERT_COLUMNS)):
        table = make([])
        assert list(table.keys() if isinstance(table, dict) else table.columns) == list(columns)
    for cls, columns in ((stsim.WarningEpisode, stsim.WARNING_COLUMNS), (stsim.Conflict, stsim.CONFLICT_COLUMNS),
                         (stsim.HindsightEvent, stsim.EVENT_COLUMNS), (stsim.Alert, stsim.ALERT_COLUMNS)):
        missing = [c for c in columns if not hasattr(cls, c)]
        assert not missing, (cls.__name__, missing)


def test_a_route_is_followed_through_a_junction():
    # a lane ends at a junction: straight on to "east", or round a left turn (a quarter circle of
    # 8 m) to "north", where a stopped car stands 10 m up; a car 10 m before the junction at
    # 20 m/s reaches it along the turn after about 1 s, not going straight on
    turn = [(8.0 * math.sin(0.5 * math.pi * k / 9), 8.0 - 8.0 * math.cos(0.5 * math.pi * k / 9)) for k in range(10)]
    lanes = [
        {"id": "in_0", "edge": "in", "shape": [(-100.0, 0.0), (0.0, 0.0)]},
        {"id": ":j_0_0", "edge": ":j_0", "shape": [(0.0, 0.0), (16.0, 0.0)], "internal": True},
        {"id": ":j_1_0", "edge": ":j_1", "shape": turn, "internal": True},
        {"id": "north_0", "edge": "north", "shape": [(8.0, 8.0), (8.0, 100.0)]},
        {"id": "east_0", "edge": "east", "shape": [(16.0, 0.0), (100.0, 0.0)], "length": 84.0},
    ]
    stopped = {"id": "stopped", "x": 8.0, "y": 18.0, "heading": 0.5 * math.pi, "speed": 0.0, "equipped": False}

    def warned(route):
        m = stsim.Monitor(lanes=lanes, detector="box", check_road=False)
        car = {"id": "car", "x": -10.0, "y": 0.0, "heading": 0.0, "speed": 20.0}
        if route is not None:
            car["route"] = route
        m.step(0.0, [car, stopped])
        return [w.foe for w in m.open_warnings()], m.counters["route_predicted_updates"]

    assert warned(["in", "north"]) == (["stopped"], 1)
    assert warned(["in", "east"]) == ([], 1)
    assert warned(None) == ([], 0)  # no route, no signal: straight on
    assert warned(["nowhere"]) == ([], 0)  # a route that does not hold its edge is none
    with pytest.raises(TypeError, match="route"):
        stsim.Monitor(lanes=lanes).step(0.0, [{"id": "c", "x": 0, "y": 0, "heading": 0, "speed": 1, "route": "in"}])
