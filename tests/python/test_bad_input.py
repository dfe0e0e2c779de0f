"""Bad input is a Python exception with a message naming the vehicle and key; never a crash, and
the monitor stays usable after it."""
import math

import numpy as np
import pytest

import stsim


def car(**kw):
    v = {"id": "a", "x": 0.0, "y": 0.0, "heading": 0.0, "speed": 20.0}
    v.update(kw)
    return v


@pytest.mark.parametrize("key,value,error,message", [
    ("x", "ten", TypeError, r"vehicle 0 \('a'\): 'x' must be a number, got str"),
    ("x", None, TypeError, r"'x' must be a number, got NoneType"),
    ("speed", True, TypeError, r"'speed' must be a number, got bool"),
    ("speed", math.nan, ValueError, r"'speed' must be finite"),
    ("heading", math.inf, ValueError, r"'heading' must be finite"),
    ("id", 7, TypeError, r"'id' must be a str, got int"),
    ("vehicle_class", "tank", ValueError, r"'vehicle_class' must be passenger, truck, .* got 'tank'"),
    ("signals", 4, ValueError, r"'signals' must be 0..3"),
    ("signals", 1.5, TypeError, r"'signals' must be an integer"),
    ("equipped", "yes", TypeError, r"'equipped' must be a bool"),
    ("spede", 1.0, ValueError, r"unknown key 'spede' \(known: id, x, y, heading, speed"),
    ("angle", 90.0, ValueError, r"unknown key 'angle' \(SUMO's navigational angle: use step_sumo"),
    ("length", -1.0, ValueError, r"vehicle 'a': length must be finite"),
])
def test_bad_vehicle_values(key, value, error, message):
    m = stsim.Monitor()
    with pytest.raises(error, match=message):
        m.step(0.0, [car(**{key: value})])
    m.step(0.1, [car()])  # still usable
    assert m.counters["ticks"] == 1


@pytest.mark.parametrize("vehicles,error,message", [
    ([car(), car()], ValueError, r"duplicate|'a'"),
    ([{"x": 0.0, "y": 0.0, "heading": 0.0, "speed": 1.0}], ValueError, r"vehicle 0: missing 'id'"),
    ([{"id": "b", "y": 0.0, "heading": 0.0, "speed": 1.0}], ValueError,
     r"vehicle 0 \('b'\): missing 'x'"),
    ([car(), "car"], TypeError, r"vehicle 1 must be a dict, got str"),
    ("cars", TypeError, r"vehicles must be a list of dicts or a dict of columns, got str"),
    (42, TypeError, r"vehicles must be a list of dicts or a dict of columns, got int"),
    ({"id": ["a", "b"], "x": np.array([0.0, 1.0]), "y": [0.0], "heading": [0, 0], "speed": [1, 1]}, ValueError,
     r"column 'y' has 1 values, the others 2"),
    ({"id": ["a"], "x": np.array([np.nan]), "y": [0.0], "heading": [0.0], "speed": [1.0]}, ValueError,
     r"vehicle 0: 'x' must be finite"),
    ({"id": ["a"], "x": 3.0, "y": [0.0], "heading": [0.0], "speed": [1.0]}, TypeError,
     r"column 'x' must be a sequence or array, got float"),
    ({"id": ["a"], "x": ["0"], "y": [0.0], "heading": [0.0], "speed": [1.0]}, TypeError,
     r"vehicle 0: 'x' must be a number, got str"),
    ({"id": ["a"], "wobble": [0.0]}, ValueError, r"column: unknown key 'wobble'"),
])
def test_bad_vehicle_lists(vehicles, error, message):
    m = stsim.Monitor()
    with pytest.raises(error, match=message):
        m.step(0.0, vehicles)


def test_time_must_increase_and_be_finite():
    m = stsim.Monitor()
    m.step(1.0, [car()])
    with pytest.raises(ValueError, match="step time must be finite"):
        m.step(math.nan, [car()])
    with pytest.raises(ValueError, match="step times must increase strictly"):
        m.step(0.5, [car()])
    with pytest.raises(TypeError):
        m.step("later", [car()])


@pytest.mark.parametrize("settings,error,message", [
    ({"detectr": "box"}, TypeError, r"unknown setting 'detectr' \(known: detector "),
    ({"detector": "sonar"}, ValueError, r"setting 'detector' must be one of concentric, five, box, got 'sonar'"),
    ({"detector": 3}, TypeError, r"setting 'detector' must be a str, got int"),
    ({"motion": "warp"}, ValueError, r"setting 'motion' must be one of velocity, acceleration"),
    ({"cells_length": 0.0}, ValueError, r"setting 'cells.length' must be in \[1, 1000000\] m, got 0"),
    ({"cells": {"length": "long"}}, TypeError, r"setting 'cells.length' must be a number"),
    ({"safe_time_vehicle_reaction": math.nan}, ValueError, r"'safe_time.vehicle_reaction' must be in \[0, 60\] s, got nan"),
    ({"safe_time": {"brake_force": {"tank": 1e5}}}, TypeError, r"unknown setting 'safe_time.brake_force.tank'"),
    ({"safe_time": {"brake_force": [1.0]}}, TypeError, r"'safe_time.brake_force' must be a dict"),
    ({"check_road": "no"}, TypeError, r"'check_road' must be a bool"),
    ({"cells_max_depth": 40}, ValueError, r"'cells.max_depth' must be in \[0, 32\], got 40"),
    ({"cells_max_depth": 2.5}, ValueError, r"'cells.max_depth' must be a whole number, got 2.5"),
])
def test_bad_settings(settings, error, message):
    with pytest.raises(error, match=message):
        stsim.Monitor(**settings)


def test_bad_network():
    with pytest.raises(ValueError, match="nope.net.xml"):
        stsim.Monitor("/nonexistent/nope.net.xml")
    with pytest.raises(TypeError, match="net must be a path to a .net.xml or None, got int"):
        stsim.Monitor(3)
    with pytest.raises(ValueError, match="lane 0: 'shape': points must be"):
        stsim.Monitor(lanes=[{"id": "e_0", "edge": "e", "shape": [(0.0, 0.0, 1.0)]}])
    with pytest.raises(ValueError, match="give net or lanes, not both"):
        stsim.Monitor("x.net.xml", lanes=[])


# Monitor.step refuses what the CLI refuses in a trace, in the same words
@pytest.mark.parametrize("key,value,message", [
    ("x", 1e300, r"vehicle 0 \('a'\): position \(1e\+300, 0\) is farther than 1e\+07 m from the origin"),
    ("speed", -5.0, r"vehicle 0 \('a'\): speed -5 m/s is negative"),
    ("speed", 1e300, r"speed 1e\+300 m/s is beyond any vehicle's"),
    ("heading", 1e300, r"vehicle 0 \('a'\): heading 1e\+300 rad is not a heading"),
    ("acceleration", 1e300, r"acceleration 1e\+300 m/s\^2 is beyond any vehicle's"),
    ("length", 1e300, r"length and width must be at most 1000 m"),
])
def test_implausible_vehicle_values(key, value, message):
    m = stsim.Monitor()
    with pytest.raises(ValueError, match=message):
        m.step(0.0, [car(**{key: value})])
    m.step(0.1, [car()])  # still usable
    assert m.counters["ticks"] == 1


def test_finish_time_must_be_finite_and_traci_monitor_needs_a_connection():
    m = stsim.Monitor()
    m.step(0.0, [car()])
    with pytest.raises(ValueError, match="finish time must be finite, got nan"):
        m.finish(math.nan)
    m.finish(1.0)
    with pytest.raises(TypeError, match=r"TraciMonitor needs a TraCI connection .* got NoneType"):
        stsim.TraciMonitor(None)


def test_a_link_state_is_one_letter():
    # SUMO's link states (its netstate and TraCI docs): the minor and stop letters give way, every
    # letter that lets a car in enters, red and yellow do neither
    assert [c for c in "GgrYyuoOswmM=Z-" if stsim.gives_way_at(c)] == list("gswm=")
    assert [c for c in "GgrYyuoOswmM=Z-" if stsim.enters_at(c)] == list("GgoOmM=")
    for bad in ("", "Gg"):
        with pytest.raises(ValueError, match="a SUMO link state is one letter"):
            stsim.gives_way_at(bad)
