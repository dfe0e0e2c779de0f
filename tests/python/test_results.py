"""What comes back: alerts against the analytic time to collision, counters, the table."""
import sys
import types

import numpy as np
import pytest

import stsim


def head_on(t, gap=100.0, v=20.0, length=5.0):
    # two cars on one line closing at 2v; centres `gap` apart at t = 0
    x = v * t
    return {"id": np.array(["a", "b"]), "x": np.array([x, gap - x]), "y": np.zeros(2),
            "heading": np.array([0.0, np.pi]), "speed": np.array([v, v]), "length": np.array([length, length])}


def test_alerts_give_the_analytic_ttc():
    m = stsim.Monitor(detector="box")
    m.step(0.0, head_on(0.0))
    alerts = {a.ego: a for a in m.alerts()}
    assert set(alerts) == {"a", "b"}
    a = alerts["a"]
    assert (a.kind, a.foe, a.vehicle, a.foe_vehicle) == ("vehicle", "b", 0, 1)
    # the box TTC of the bumpers: (100 - 5) / 40 s; the safe time 1 s + 1500 kg * 40 m/s / (2 * 12 kN)
    assert a.ttc == pytest.approx(95.0 / 40.0, rel=1e-12)
    assert a.safe_time == pytest.approx(1.0 + 1500.0 * 40.0 / 24000.0, rel=1e-12)
    assert [w.ego for w in m.open_warnings()] and all(w.open for w in m.open_warnings())
    m.step(0.5, head_on(0.5))
    assert {x.ego: x.ttc for x in m.alerts()}["b"] == pytest.approx((95.0 - 20.0) / 40.0, rel=1e-12)
    m.finish()  # at the last step's time, 0.5 s
    done = m.take_finished()
    assert sorted((w.ego, w.foe) for w in done) == [("a", "b"), ("b", "a")]
    assert all(w.min_ttc == pytest.approx(75.0 / 40.0, rel=1e-12) and w.begin == 0.0 for w in done)
    c = m.counters
    assert (c["ticks"], c["vehicles_seen"], c["warnings_by_kind"]["vehicle"]) == (2, 2, 2)


def test_far_apart_is_no_warning():
    m = stsim.Monitor(detector="box")
    m.step(0.0, head_on(0.0, gap=2000.0))
    assert m.alerts() == [] and m.open_warnings() == []


def test_warnings_table_uses_pandas_when_there(monkeypatch):
    m = stsim.Monitor(detector="box")
    m.step(0.0, head_on(0.0))
    m.finish(0.0)
    ws = m.take_finished()
    table = stsim.warnings_table(ws)
    if isinstance(table, dict):  # no pandas: columns of warnings.csv
        assert list(table) == list(stsim.WARNING_COLUMNS) and table["foe"] == [w.foe for w in ws]
    fake = types.ModuleType("pandas")
    fake.DataFrame = lambda cols: ("frame", cols)
    monkeypatch.setitem(sys.modules, "pandas", fake)
    kind, cols = stsim.warnings_table(ws)
    assert kind == "frame" and cols["min_ttc"] == [w.min_ttc for w in ws]


def test_finish_without_a_time_closes_at_the_last_step():
    # finish() and finish(last_time) close the same episodes at the same end (as TraciMonitor.finish())
    ends = []
    for close in (lambda m: m.finish(), lambda m: m.finish(m.last_time)):
        m = stsim.Monitor(detector="box")
        m.step(0.0, head_on(0.0))
        m.step(0.25, head_on(0.25))
        close(m)
        ends.append(sorted((w.ego, w.end, w.open) for w in m.take_finished()))
    assert ends[0] == ends[1] and [e[1] for e in ends[0]] == [0.25, 0.25]


def test_help_gives_every_setting_with_its_default():
    doc = stsim.Monitor.__doc__
    settings = stsim.Monitor().settings  # the defaults in effect
    for key, value in settings.items():
        shown = ("true" if value else "false") if isinstance(value, bool) else None
        line = next((ln for ln in doc.splitlines() if ln.strip().startswith(key + " = ")), None)
        assert line is not None, key
        if shown is not None:
            assert line.strip().startswith(f"{key} = {shown} "), line
        elif isinstance(value, str):
            assert line.strip().startswith(f"{key} = {value} "), line
        else:
            assert float(line.strip().split(" = ")[1].split()[0]) == pytest.approx(value), line
