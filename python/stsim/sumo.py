"""stsim on a running SUMO: the states of every vehicle read through a Python TraCI connection
(the `traci` module, a `traci.Connection`, or `libsumo`, which has the same API) and handed to the
monitor in SUMO's conventions (front bumper, navigational degrees), where they are converted by
the same code as stsim's own SUMO coupling. The reads follow the coupling's: position, angle,
speed, lateral speed; acceleration only for the constant-acceleration motion model, turn signals
only when the road is checked, the route only for the road prediction; size, class and the
vType's "mass" param once per type."""
import math

from ._stsim import Monitor


def read_traci_lanes(conn):
    """Every lane of the loaded network as Monitor(lanes=...) takes it (internal lanes included)."""
    lanes = []
    for lane_id in conn.lane.getIDList():
        index = lane_id.rsplit("_", 1)[-1]
        lanes.append({
            "id": lane_id,
            "edge": conn.lane.getEdgeID(lane_id),
            "index": int(index) if index.isdigit() else 0,
            "width": conn.lane.getWidth(lane_id),
            "length": conn.lane.getLength(lane_id),
            "shape": [tuple(p) for p in conn.lane.getShape(lane_id)],
            "internal": lane_id.startswith(":"),
        })
    return lanes


def _vehicle_type(conn, type_id):
    mass = conn.vehicletype.getParameter(type_id, "mass")
    info = {
        "vehicle_class": conn.vehicletype.getVehicleClass(type_id),
        "length": conn.vehicletype.getLength(type_id),
        "width": conn.vehicletype.getWidth(type_id),
    }
    if mass:
        try:
            m = float(mass)
        except ValueError:
            m = float("nan")
        if not (m > 0.0 and math.isfinite(m)):
            raise ValueError(f"vType '{type_id}': param 'mass' must be a positive number of kg, got '{mass}'")
        info["mass"] = m
    return info


def read_traci_vehicles(conn, types=None, acceleration=True, signals=True, route=True):
    """Every vehicle's state now, as columns in SUMO's conventions (Monitor.step_sumo takes them).
    `types` caches the vTypes between calls (a dict, filled here). With `route`, each vehicle's
    route from its current edge on (what the road prediction follows through junctions)."""
    if types is None:
        types = {}
    v = conn.vehicle
    ids = list(v.getIDList())
    cols = {k: [] for k in ("x", "y", "angle", "speed", "lateral_speed", "length", "width", "vehicle_class")}
    cols["id"] = ids
    if acceleration:
        cols["acceleration"] = []
    if signals:
        cols["signals"] = []
    if route:
        cols["route"] = []
    masses = []
    for vid in ids:
        x, y = v.getPosition(vid)
        cols["x"].append(x)
        cols["y"].append(y)
        cols["angle"].append(v.getAngle(vid))
        cols["speed"].append(v.getSpeed(vid))
        cols["lateral_speed"].append(v.getLateralSpeed(vid))
        if acceleration:
            cols["acceleration"].append(v.getAcceleration(vid))
        if signals:
            cols["signals"].append(v.getSignals(vid))
        if route:
            cols["route"].append(list(v.getRoute(vid))[max(0, v.getRouteIndex(vid)):])
        type_id = v.getTypeID(vid)
        t = types.get(type_id)
        if t is None:
            t = types[type_id] = _vehicle_type(conn, type_id)
        cols["length"].append(t["length"])
        cols["width"].append(t["width"])
        cols["vehicle_class"].append(t["vehicle_class"])
        masses.append(t.get("mass"))
    if any(m is not None for m in masses):
        if all(m is not None for m in masses):
            cols["mass"] = masses
        else:  # the class default for types without a mass param, as the SUMO coupling does
            return _rows(cols, masses)
    return cols


def _rows(cols, masses):
    keys = list(cols)
    rows = []
    for i, m in enumerate(masses):
        row = {k: cols[k][i] for k in keys}
        if m is not None:
            row["mass"] = m
        rows.append(row)
    return rows


class TraciMonitor:
    """A Monitor fed from a TraCI connection: step() after each simulationStep().

    TraciMonitor(conn, net=None, **settings): conn is `traci`, a `traci.Connection` or `libsumo`;
    the road comes from `net` (a .net.xml) or, without it, from the lanes SUMO has loaded;
    settings are Monitor's. take_finished(), take_events(), open_warnings(), alerts(), counters, finish() as
    Monitor's (finish() without a time closes at SUMO's current time)."""

    def __init__(self, conn, net=None, **settings):
        self.conn = conn
        self.monitor = Monitor(net, **settings) if net is not None else Monitor(lanes=read_traci_lanes(conn), **settings)
        self._acceleration = settings.get("motion", "velocity") == "acceleration"
        self._signals = settings.get("check_road", True)
        self._route = settings.get("prediction", "road") == "road"
        self._types = {}

    def step(self):
        states = read_traci_vehicles(self.conn, self._types, self._acceleration, self._signals, self._route)
        self.monitor.step_sumo(self.conn.simulation.getTime(), states)

    def finish(self, t=None):
        self.monitor.finish(self.conn.simulation.getTime() if t is None else t)

    def take_finished(self):
        return self.monitor.take_finished()

    def take_events(self):
        return self.monitor.take_events()

    def open_warnings(self):
        return self.monitor.open_warnings()

    def alerts(self):
        return self.monitor.alerts()

    @property
    def counters(self):
        return self.monitor.counters
