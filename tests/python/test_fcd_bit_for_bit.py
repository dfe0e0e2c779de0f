"""The module gives the C++ monitor's results bit for bit: every shipped FCD run replayed through
Python (a list of dicts per tick, and NumPy columns) against `stsim highway --fcd` (its
warnings.csv, written with %.17g, so every double round-trips)."""
import csv

import numpy as np
import pytest

import stsim
from conftest import DATA, SOURCE, run_stsim

TRACES = {
    "lanedrop": (DATA / "lanedrop.fcd.xml", DATA / "lanedrop.net.xml", DATA / "lanedrop.rou.xml"),
    "motorway_merge": (DATA / "motorway_merge.fcd.xml", SOURCE / "networks/motorway/motorway.net.xml",
                       SOURCE / "networks/motorway/motorway.rou.xml"),
}
NUMERIC = ("begin", "end", "min_ttc", "min_ttc_time", "safe_time")


def cli_rows(binary, tmp_path, fcd, net, vtypes, detector, motion):
    out = tmp_path / f"cli_{detector}_{motion}"
    r = run_stsim(binary, "highway", "--fcd", fcd, "--net", net, "--vtypes", vtypes, "--detector", detector,
                  "--motion", motion, "--out", out, "--no-map")
    assert r.returncode == 0, r.stderr
    with open(out / "warnings.csv", newline="") as f:
        rows = list(csv.DictReader(f))
    return [(r["ego"], r["foe"], r["kind"], r["zone"], *(float(r[k]) for k in NUMERIC), r["open"] == "1")
            for r in rows]


def as_columns(vehicles):
    cols = {k: [v[k] for v in vehicles] for k in vehicles[0]}
    for k in ("x", "y", "heading", "speed", "lateral_speed", "acceleration", "length", "width", "mass"):
        cols[k] = np.array(cols[k], dtype=np.float64)
    cols["signals"] = np.array(cols["signals"], dtype=np.int64)
    return cols


def python_rows(fcd, net, vtypes, detector, motion, columns):
    m = stsim.Monitor(str(net), detector=detector, motion=motion)
    finished = []
    last = 0.0
    for t, vehicles in stsim.FcdReader(fcd, vtypes):
        m.step(t, as_columns(vehicles) if columns and vehicles else vehicles)
        finished += m.take_finished()
        last = t
    m.finish(last)
    finished += m.take_finished()
    return [(w.ego, w.foe, w.kind, w.zone, w.begin, w.end, w.min_ttc, w.min_ttc_time, w.safe_time, w.open)
            for w in finished]


@pytest.mark.parametrize("trace", sorted(TRACES))
@pytest.mark.parametrize("detector,motion", [("five", "velocity"), ("concentric", "velocity"), ("box", "acceleration")])
def test_replay_equals_the_cli(stsim_binary, tmp_path, trace, detector, motion):
    fcd, net, vtypes = TRACES[trace]
    want = cli_rows(stsim_binary, tmp_path, fcd, net, vtypes, detector, motion)
    assert len(want) > 10  # a run with warnings of every kind it can have
    # along the lanes a lane change SUMO makes in one step is no lateral motion: the motorway's
    # marker warnings go; the sublane trace's drifts across markers stay
    kinds = {w[2] for w in want}
    assert "vehicle" in kinds and ("lane_marker" in kinds or trace == "motorway_merge")
    for columns in (False, True):
        got = python_rows(fcd, net, vtypes, detector, motion, columns)
        assert got == want, f"columns={columns}"  # exact float equality, same order


def test_every_shipped_trace_is_covered():
    shipped = {p.name.removesuffix(".fcd.xml") for p in DATA.glob("*.fcd.xml")} - {"bad_angle"}
    assert shipped == set(TRACES)


def test_fcd_reader_reports_file_and_line():
    with pytest.raises(stsim.InputError, match=r"bad_angle\.fcd\.xml:5"):
        list(stsim.FcdReader(DATA / "bad_angle.fcd.xml"))
    with pytest.raises(stsim.InputError) as e:
        list(stsim.FcdReader(DATA / "nope.fcd.xml"))
    assert "nope.fcd.xml" in str(e.value)
