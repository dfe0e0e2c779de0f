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
    assert (a.kind, a.foe_id, a.vehicle, a.foe) == ("vehicle", "b", 0, 1)
    # the box TTC of the bumpers: (100 - 5) / 40 s; the safe time 1 s + 1500 kg * 40 m/s / (2 * 12 kN)
    assert a.ttc == pytest.approx(95.0 / 40.0, rel=1e-12)
    assert a.safe_time == pytest.approx(1.0 + 1500.0 * 40.0 / 24000.0, rel=1e-12)
    assert [w.ego for w in m.open_warnings()] and all(w.open for w in m.open_warnings())
    m.step(0.5, head_on(0.5))
    assert {x.ego: x.ttc for x in m.alerts()}["b"] == pytest.approx((95.0 - 20.0) / 40.0, rel=1e-12)
    m.finish(0.5)
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
