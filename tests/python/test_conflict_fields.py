"""Every column of warnings.csv and summary.json's hindsight counters come back through Python
equal to `stsim highway --fcd ... --net` on the same trace: hindsight's verdict and realized
columns, the conflict record (position, lane, speeds, angle, type, DRAC, MaxDeltaV, line, lateral
speed). warnings.csv writes every input-derived double so that it reads back exactly and every
measure worked out from them to 0.001 (Python's to the same 0.001 here), and leaves a cell empty
where the column does not apply: Python's None."""
import csv
import json
import math

import numpy as np
import pytest

import stsim
from conftest import run_stsim
from test_fcd_bit_for_bit import TRACES, as_columns

BOOLEAN = ("open", "crossed", "signalled")
# worked out from the inputs: written to 0.001 of their unit (docs/outputs.md), Python's in full
DERIVED = ("conflict_x", "conflict_y", "delta_s", "dr", "max_d", "conflict_angle", "post_crash_speed",
           "post_crash_heading", "pet", "heading_angle", "drac", "max_delta_v")
TEXT = ("ego", "foe", "kind", "zone", "verdict", "lane", "type", "line")


def cell(column, text):
    """A warnings.csv cell as the value Python gives for it."""
    if column in TEXT:
        return text
    if text == "":
        return None
    if column in BOOLEAN:
        assert text in ("0", "1"), (column, text)
        return text == "1"
    return float(text)  # "inf" too (an infinite DRAC)


def as_written(column, value):
    """A WarningEpisode field as warnings.csv writes it: a derived measure to 0.001."""
    return float("%.3f" % value) if column in DERIVED and value is not None and math.isfinite(value) else value


def cli_run(binary, tmp_path, fcd, net, vtypes, detector, motion, prediction):
    out = tmp_path / f"cli_{detector}_{motion}_{prediction}"
    out.parent.mkdir(parents=True, exist_ok=True)
    r = run_stsim(binary, "highway", "--fcd", fcd, "--net", net, "--vtypes", vtypes, "--detector", detector,
                  "--motion", motion, "--prediction", prediction, "--out", out, "--no-map")
    assert r.returncode == 0, r.stderr
    with open(out / "warnings.csv", newline="") as f:
        reader = csv.DictReader(f)
        assert tuple(reader.fieldnames) == stsim.WARNING_COLUMNS  # the same columns, in order
        rows = [tuple(cell(c, row[c]) for c in stsim.WARNING_COLUMNS) for row in reader]
    with open(out / "summary.json") as f:
        summary = json.load(f)
    return rows, summary


def python_run(fcd, net, vtypes, detector, motion, prediction, columns):
    m = stsim.Monitor(str(net), detector=detector, motion=motion, prediction=prediction)
    finished = []
    last = 0.0
    for t, vehicles in stsim.FcdReader(fcd, vtypes, net=net):
        m.step(t, as_columns(vehicles) if columns and vehicles else vehicles)
        finished += m.take_finished()
        last = t
    m.finish(last)
    finished += m.take_finished()
    return [tuple(as_written(c, getattr(w, c)) for c in stsim.WARNING_COLUMNS) for w in finished], m.counters


def lead_quantiles(leads):
    # summary.json's rule (models/highway/src/report.cpp): sorted, the element nearest f (n - 1)
    if not leads:
        return None
    v = sorted(leads)
    q = lambda f: v[int(f * (len(v) - 1) + 0.5)]
    return {"min": v[0], "median": q(0.5), "p90": q(0.9)}


SETTINGS = [("five", "velocity", "road"), ("concentric", "velocity", "road"), ("box", "acceleration", "road"),
            ("five", "velocity", "straight")]


def test_the_comparison_covers_every_column(stsim_binary, tmp_path):
    # over the cases compared below: judged warnings of both verdicts, lanes, road lines, the
    # vehicle and road columns of hindsight, and the conflict types (a short trace under road
    # prediction may have no road warning, so this holds for the cases together)
    col = {c: i for i, c in enumerate(stsim.WARNING_COLUMNS)}
    rows = []
    for trace, (fcd, net, vtypes) in TRACES.items():
        for detector, motion, prediction in SETTINGS:
            rows += cli_run(stsim_binary, tmp_path / trace, fcd, net, vtypes, detector, motion, prediction)[0]
    assert {"confirmed", "nuisance"} <= {w[col["verdict"]] for w in rows}
    assert any(w[col["lane"]] for w in rows) and any(w[col["line"]] for w in rows)
    assert {"road", "rear_end"} <= {w[col["type"]] for w in rows}
    for c in ("clearance", "clearance_time", "deceleration", "crossed", "signalled", "foe_speed", "max_delta_v",
              "lateral_speed"):
        assert any(w[col[c]] is not None for w in rows), c
        assert any(w[col[c]] is None for w in rows), c  # and where it does not apply
    assert all(w[col["heading_angle"]] is not None for w in rows)  # None only for a hazard: none here


@pytest.mark.parametrize("trace", sorted(TRACES))
@pytest.mark.parametrize("detector,motion,prediction", SETTINGS)
def test_every_column_and_the_hindsight_counters_equal_the_cli(stsim_binary, tmp_path, trace, detector, motion,
                                                               prediction):
    fcd, net, vtypes = TRACES[trace]
    want, summary = cli_run(stsim_binary, tmp_path, fcd, net, vtypes, detector, motion, prediction)
    assert len(want) > 10  # a run with warnings to compare
    for columns in (False, True):
        got, counters = python_run(fcd, net, vtypes, detector, motion, prediction, columns)
        assert got == want, f"columns={columns}"  # exact float equality, None where the cell is empty

        h, hw = counters["hindsight"], summary["hindsight"]
        for kind, k in hw["by_kind"].items():
            assert (h["by_kind"][kind]["judged"], h["by_kind"][kind]["confirmed"]) == (k["judged"], k["confirmed"])
            assert h["by_kind"][kind]["precision"] == k["precision"]  # None where summary.json has null
        nm, nw = h["near_misses"], hw["near_misses"]
        assert (nm["events"], nm["warned"], nm["recall"]) == (nw["events"], nw["warned"], nw["recall"])
        assert len(nm["lead_times_s"]) == nw["warned"]
        assert lead_quantiles(nm["lead_times_s"]) == nw["lead_s"]
        assert counters["warnings_by_type"] == summary["warnings"]["by_type"]
        assert (counters["road_predicted_updates"], counters["straight_fallback_updates"]) == \
            (summary["road_predicted_updates"], summary["straight_fallback_updates"])
        assert (counters["road_predicted_updates"] > 0) == (prediction == "road")


def test_the_table_has_every_column():
    m = stsim.Monitor(detector="box")
    for t in (0.0, 0.1):
        m.step(t, [{"id": "a", "x": 25.0 * t, "y": 0.0, "heading": 0.0, "speed": 25.0},
                   {"id": "b", "x": 30.0, "y": 0.0, "heading": 0.0, "speed": 5.0}])
    m.finish(0.1)
    ws = m.take_finished()
    assert ws
    table = stsim.warnings_table(ws)
    if not isinstance(table, dict):  # pandas: a DataFrame
        table = {c: list(table[c]) for c in table.columns}
    assert list(table) == list(stsim.WARNING_COLUMNS)
    w = next(w for w in ws if w.ego == "a")
    # a rear-end on a straight line: both speeds, no road line, parallel headings
    assert (w.type, w.ego_speed, w.foe_speed, w.heading_angle, w.line, w.lateral_speed) == \
        ("rear_end", 25.0, 5.0, 0.0, "", None)
    assert w.drac > 0 and math.isfinite(w.drac) and w.max_delta_v == pytest.approx(10.0)  # equal masses: dv / 2


def test_a_lane_the_network_lacks_is_none_and_an_unknown_lane_no_lane():
    fcd, net, vtypes = TRACES["lanedrop"]
    t, vehicles = next(iter(stsim.FcdReader(fcd, vtypes, net=net)))
    assert vehicles and all(isinstance(v["lane"], str) for v in vehicles)
    assert "lane" not in next(iter(stsim.FcdReader(fcd, vtypes)))[1][0]  # without the net, no lane
    m = stsim.Monitor(str(net))
    v = dict(vehicles[0], lane="no_such_lane")
    m.step(t, [v])  # as the FCD reader: a lane the road lacks is unknown, not an error
    with pytest.raises(TypeError, match="'lane' must be a str"):
        m.step(t + 1.0, [dict(vehicles[0], lane=3)])
    cols = as_columns(vehicles)
    cols["lane"] = np.array([v["lane"] for v in vehicles])
    m2 = stsim.Monitor(str(net))
    m2.step(t, cols)  # NumPy str columns too


def test_hindsight_and_conflict_settings():
    # the scenario's keys: nested dicts, or flat with '_' for '.'
    assert stsim.Monitor(hindsight={"enabled": False}).counters["hindsight"] is None
    assert stsim.Monitor(hindsight_enabled=False).counters["hindsight"] is None
    h = stsim.Monitor(hindsight={"clearance": 0.7, "evasive_deceleration": 5.0}, hindsight_lead=0.25).counters["hindsight"]
    assert (h["clearance_m"], h["evasive_deceleration"], h["lead_s"]) == (0.7, 5.0, 0.25)
    assert h["by_kind"]["vehicle"] == {"judged": 0, "confirmed": 0, "precision": None}  # nothing to count
    assert h["near_misses"]["recall"] is None
    with pytest.raises(ValueError, match="conflict.crossing_above' must be at least conflict.rear_end_below"):
        stsim.Monitor(conflict={"rear_end_below": 60.0, "crossing_above": 40.0})
    with pytest.raises(ValueError, match=r"conflict.rear_end_below' must be in \[0, 180\] deg, got 200"):
        stsim.Monitor(conflict_rear_end_below=200.0)
    with pytest.raises(ValueError, match="clearance"):
        stsim.Monitor(hindsight_clearance=-1.0)
    with pytest.raises(ValueError, match="prediction' must be one of road, straight"):
        stsim.Monitor(prediction="curved")
