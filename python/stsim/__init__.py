"""stsim: smart-car collision warnings (stsim's highway model) for Python.

    import stsim
    monitor = stsim.Monitor("networks/motorway/motorway.net.xml", detector="five")
    monitor.step(0.1, [{"id": "a", "x": 10.0, "y": -4.8, "heading": 0.0, "speed": 30.0}, ...])
    for w in monitor.take_finished(): print(w.ego, w.foe, w.kind, w.min_ttc)

With SUMO (a TraCI script, or libsumo), three lines:

    monitor = stsim.TraciMonitor(traci)          # after traci.start([...])
    traci.simulationStep(); monitor.step()       # each step
    monitor.finish(); stsim.warnings_table(monitor.take_finished())

The results are the C++ monitor's (the same code), bit for bit.
"""
import os

# SUMO validates its input against the XML schemas under SUMO_HOME and fails without them; set it
# for Debian's sumo as stsim's C++ SUMO coupling does (before the caller's traci.start)
if "SUMO_HOME" not in os.environ and os.path.isdir("/usr/share/sumo/data/xsd"):
    os.environ["SUMO_HOME"] = "/usr/share/sumo"

from ._stsim import (CONFLICT_COLUMNS, EVENT_COLUMNS, WARNING_COLUMNS, Alert, Conflict, FcdReader, HindsightEvent,
                     InputError, Monitor, WarningEpisode, __version__, enters_at, gives_way_at)
from .sumo import TraciMonitor, TraciVehicleReader, read_traci_lanes, read_traci_persons, read_traci_vehicles

__all__ = ["Alert", "Conflict", "FcdReader", "HindsightEvent", "InputError", "Monitor", "WarningEpisode", "TraciMonitor",
           "TraciVehicleReader", "read_traci_lanes", "read_traci_persons", "read_traci_vehicles", "warnings_table",
           "conflicts_table", "events_table", "alerts_table", "WARNING_COLUMNS", "CONFLICT_COLUMNS", "EVENT_COLUMNS",
           "ALERT_COLUMNS", "__version__", "gives_way_at", "enters_at"]

# WARNING_COLUMNS, CONFLICT_COLUMNS, EVENT_COLUMNS: the columns of stsim highway's warnings.csv,
# conflicts.csv and events.csv, in their order, taken from the C++ writers' headers; a
# WarningEpisode, Conflict and HindsightEvent has each as an attribute (docs/outputs.md says what
# each means). An Alert has ALERT_COLUMNS.
ALERT_COLUMNS = ("vehicle", "ego", "kind", "zone", "ttc", "safe_time", "foe", "foe_vehicle")


def _table(records, columns):
    """records as a table with the given columns: a pandas DataFrame when pandas is installed,
    else a dict of lists (which pandas.DataFrame() also takes). A cell the CSV file leaves empty
    (the column does not apply, or the record is not judged) is None (NaN in a pandas number
    column)."""
    data = {c: [getattr(r, c) for r in records] for c in columns}
    try:
        import pandas
    except ImportError:
        return data
    return pandas.DataFrame(data)  # the dict keeps the columns in order


def warnings_table(warnings):
    """Warning episodes (WarningEpisode) as a table with warnings.csv's columns."""
    return _table(warnings, WARNING_COLUMNS)


def conflicts_table(conflicts):
    """Conflicts (Conflict, Monitor.take_conflicts) as a table with conflicts.csv's columns."""
    return _table(conflicts, CONFLICT_COLUMNS)


def events_table(events):
    """Near misses and unsignalled crossings (HindsightEvent, Monitor.take_events) as a table with
    events.csv's columns."""
    return _table(events, EVENT_COLUMNS)


def alerts_table(alerts):
    """Alerts (Monitor.alerts) as a table with ALERT_COLUMNS."""
    return _table(alerts, ALERT_COLUMNS)
