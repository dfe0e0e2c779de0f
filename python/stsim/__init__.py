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

from ._stsim import Alert, FcdReader, InputError, Monitor, WarningEpisode, __version__
from .sumo import TraciMonitor, TraciVehicleReader, read_traci_lanes, read_traci_vehicles

__all__ = ["Alert", "FcdReader", "InputError", "Monitor", "WarningEpisode", "TraciMonitor", "TraciVehicleReader", "read_traci_lanes",
           "read_traci_vehicles", "warnings_table", "WARNING_COLUMNS", "__version__"]

# the columns of stsim's warnings.csv, in its order: the episode, hindsight, the conflict record
# (models/highway/README.md); a WarningEpisode has each as an attribute
WARNING_COLUMNS = ("ego", "foe", "kind", "zone", "begin", "end", "min_ttc", "min_ttc_time", "safe_time", "open",
                   "verdict", "clearance", "clearance_time", "deceleration", "crossed", "signalled",
                   "conflict_x", "conflict_y", "foe_x", "foe_y", "max_s", "delta_s", "dr", "max_d", "conflict_angle",
                   "clock_angle", "start_x", "start_y", "end_x", "end_y", "post_crash_speed", "post_crash_heading", "pet",
                   "x", "y", "lane", "ego_speed", "foe_speed", "heading_angle", "type", "drac", "max_delta_v", "line",
                   "lateral_speed")


def warnings_table(warnings):
    """Warning episodes as a table with warnings.csv's columns: a pandas DataFrame when pandas is
    installed, else a dict of lists (which pandas.DataFrame() also takes). A cell warnings.csv
    leaves empty (the column does not apply, or the episode is not judged) is None (NaN in a
    pandas number column)."""
    columns = {c: [getattr(w, c) for w in warnings] for c in WARNING_COLUMNS}
    try:
        import pandas
    except ImportError:
        return columns
    return pandas.DataFrame(columns)
