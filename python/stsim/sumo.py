"""stsim on a running SUMO: the states of every vehicle read through a Python TraCI connection
(the `traci` module, a `traci.Connection`, or `libsumo`, which has the same API) and handed to the
monitor in SUMO's conventions (front bumper, navigational degrees), where they are converted by
the same code as stsim's own SUMO coupling. The reads follow the coupling's: position, angle,
speed, lateral speed; acceleration only for the constant-acceleration motion model, turn signals
only when the road is checked, the route only for the road prediction; size, class and the
vType's "mass" param once per type; the next traffic light's link state and distance (with the
route, on a network with lights: each light's state once a step, its links once); the persons on
foot (position, angle, speed), after the vehicles, never equipped."""
import math

from ._stsim import Monitor, enters_at, gives_way_at


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
        "decel": conn.vehicletype.getDecel(type_id),
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


# TraCI's variable ids (traci.constants; libsumo has the same), so that this module needs neither
_POSITION, _ANGLE, _SPEED, _LATERAL_SPEED = 0x42, 0x43, 0x40, 0x32
_ACCELERATION, _SIGNALS, _TYPE, _ROUTE_ID, _ROUTE_INDEX = 0x72, 0x5b, 0x4f, 0x53, 0x69
_LANE_ID, _LANE_POSITION, _PERSON_VEHICLE = 0x51, 0x56, 0xc3


class _SignalBook:
    """Each vehicle's next point to stop or give way at, as the C++ coupling reads it (cosim's
    SignalBook): the state of the link its route takes at the end of its lane (a light's, read once
    a step; an unsignalled junction's fixed one) and the distance to that lane's end (the stop
    line), or to the wait point inside the junction where SUMO holds a turner (an internal lane
    whose exit link is minor; then m). With `priority` false, the lights only. A vehicle on a major
    link with no wait point, past its wait point, or at the end of its route has none."""

    def __init__(self, conn, priority=True):
        self.ids = list(conn.trafficlight.getIDList())
        self.priority = priority
        self.links = {}        # (from edge, to edge) -> (light or -1, link index, fixed state, wait m): the first link
        self.lane_length = {}  # lanes ending at a light or a yield -> their length (m)
        self.wait_length = {}  # internal lanes ending at a wait point -> their length (m)
        for k, tls in enumerate(self.ids):
            for i, links in enumerate(conn.trafficlight.getControlledLinks(tls)):
                for link in links:
                    from_lane, via, to_lane = link[0], link[2], link[1]
                    if not from_lane or not to_lane:
                        continue
                    self.links.setdefault((conn.lane.getEdgeID(from_lane), conn.lane.getEdgeID(to_lane)),
                                          (k, i, "", self._wait_of(conn, via)))
                    if from_lane not in self.lane_length:
                        self.lane_length[from_lane] = conn.lane.getLength(from_lane)
        # the junctions without a light (lanes in id order, as the C++ coupling and a replay take them)
        for lane in sorted(conn.lane.getIDList()):
            if lane.startswith(":"):
                continue
            for approached, approached_internal, state in _lane_links(conn, lane):
                if len(state) != 1:
                    continue
                wait = self._wait_of(conn, approached_internal)
                if not gives_way_at(state) and wait == 0.0:
                    continue
                self.links.setdefault((conn.lane.getEdgeID(lane), conn.lane.getEdgeID(approached)), (-1, 0, state, wait))
                if lane not in self.lane_length:
                    self.lane_length[lane] = conn.lane.getLength(lane)
        self.states = []

    def _wait_of(self, conn, via):
        if not via or not via.startswith(":"):
            return 0.0
        if via in self.wait_length:
            return self.wait_length[via]
        for _, approached_internal, state in _lane_links(conn, via):
            if state == "m" and approached_internal:
                self.wait_length[via] = conn.lane.getLength(via)
                return self.wait_length[via]
        return 0.0

    def any(self):
        return bool(self.ids) or (self.priority and bool(self.links))

    def read_states(self, conn):
        self.states = [conn.trafficlight.getRedYellowGreenState(t) for t in self.ids]

    def next(self, route, where):
        """(link state letter, m to where it stops or gives way) or (None, 0.0); route: the edges
        from the vehicle's current one on; where(): its lane id and position on it, asked only when
        the route's next step passes a light or a yield."""
        if route is None or len(route) < 2:
            return None, 0.0
        link = self.links.get((route[0], route[1]))
        if link is None:
            return None, 0.0
        light, index, state, wait = link
        if light < 0 and not self.priority:
            return None, 0.0
        if light >= 0:
            states = self.states[light]
            if index >= len(states):
                return None, 0.0
            state = states[index]
        lane, position = where()
        length = self.lane_length.get(lane)
        if length is not None:
            if self.priority and wait > 0.0 and enters_at(state):
                return "m", max(0.0, length - position) + wait
            return state, max(0.0, length - position)
        wait_here = self.wait_length.get(lane)
        if self.priority and wait_here is not None:  # in the junction, before its wait point
            return "m", max(0.0, wait_here - position)
        return None, 0.0


def _lane_links(conn, lane):
    """(approached lane, its first internal lane, state) of each link leaving lane: TraCI gives them
    as tuples when asked for the extended form, libsumo's module (no such argument) as objects or
    the same tuples."""
    try:
        links = conn.lane.getLinks(lane, True)
    except TypeError:
        links = conn.lane.getLinks(lane)
    return [(c.approachedLane, c.approachedInternal, c.state) if hasattr(c, "approachedLane") else (c[0], c[4], c[5])
            for c in links]


def _is_libsumo(conn):
    return getattr(conn, "__name__", "").split(".")[0] == "libsumo"


class TraciVehicleReader:
    """Reads every vehicle's state after a step, as read_traci_vehicles does, with as few calls as
    the connection needs.

    With `subscribe`, each vehicle is subscribed once, when it first has no results, to the
    variables the monitor takes; a step then costs two calls (the id list and every result) plus
    one per newly departed vehicle, and the edges of a route are asked once per route id. Without
    it, one getter per variable and vehicle. `subscribe=None` picks the faster per backend, as
    measured in bench/python_monitor: getters for libsumo (a call is a C++ function call there),
    subscriptions over a TraCI socket (a call is a round trip). Both read the same values, bit for
    bit (tests/python/test_sumo.py)."""

    def __init__(self, conn, acceleration=True, signals=True, route=True, subscribe=None, lights=True, persons=True,
                 priority=True):
        self.conn = conn
        self.acceleration, self.signals, self.route, self.persons = acceleration, signals, route, persons
        self.subscribe = (not _is_libsumo(conn)) if subscribe is None else bool(subscribe)
        self.types = {}
        # the lights matter only along a route (the stop line ahead on it)
        self.lights = _SignalBook(conn, priority) if lights and route else None
        if self.lights is not None and not self.lights.any():
            self.lights = None
        self._variables = [_POSITION, _ANGLE, _SPEED, _LATERAL_SPEED, _TYPE]
        if acceleration:
            self._variables.append(_ACCELERATION)
        if signals:
            self._variables.append(_SIGNALS)
        if route:
            self._variables += [_ROUTE_ID, _ROUTE_INDEX]
        if self.lights is not None:
            self._variables += [_LANE_ID, _LANE_POSITION]
        self._routes = {}  # vehicle id -> (route id, its edges)

    def read(self):
        """Every vehicle's state now, as read_traci_vehicles returns it, followed by the persons on
        foot (read_traci_persons) when there are any."""
        if self.lights is not None:
            self.lights.read_states(self.conn)
        vehicles = self._read_vehicles()
        if not self.persons:
            return vehicles
        persons = self._read_persons()
        if not persons:
            return vehicles
        rows = vehicles if isinstance(vehicles, list) else [dict(zip(vehicles, v)) for v in zip(*vehicles.values())]
        return rows + persons

    def _read_persons(self):
        if not self.subscribe:
            return read_traci_persons(self.conn, self.types)
        p = self.conn.person
        ids = list(p.getIDList())
        results = p.getAllSubscriptionResults()
        for pid in ids:
            if pid not in results:
                p.subscribe(pid, [_POSITION, _ANGLE, _SPEED, _TYPE, _PERSON_VEHICLE])
        results = p.getAllSubscriptionResults()
        return _person_rows(self.conn, [pid for pid in ids if not results[pid][_PERSON_VEHICLE]], self.types,
                            lambda pid: (results[pid][_POSITION], results[pid][_ANGLE], results[pid][_SPEED],
                                         results[pid][_TYPE]))

    def _read_vehicles(self):
        if not self.subscribe:
            return read_traci_vehicles(self.conn, self.types, self.acceleration, self.signals, self.route, self.lights)
        v = self.conn.vehicle
        ids = list(v.getIDList())
        results = v.getAllSubscriptionResults()
        for vid in ids:
            if vid not in results:  # departed since the last read (a subscription ends with its vehicle)
                v.subscribe(vid, self._variables)
        results = v.getAllSubscriptionResults()
        if len(self._routes) > 2 * len(ids) + 64:  # forget the routes of vehicles that left
            self._routes = {vid: self._routes[vid] for vid in ids if vid in self._routes}

        def state(vid):
            r = results[vid]
            route = None
            if self.route:
                known = self._routes.get(vid)
                if known is None or known[0] != r[_ROUTE_ID]:  # a reroute gives the vehicle a new route id
                    known = self._routes[vid] = (r[_ROUTE_ID], list(v.getRoute(vid)))
                route = known[1][max(0, r[_ROUTE_INDEX]):]
            light = (self.lights.next(route, lambda: (r[_LANE_ID], r[_LANE_POSITION]))
                     if self.lights is not None else None)
            return (r[_POSITION], r[_ANGLE], r[_SPEED], r[_LATERAL_SPEED],
                    r[_ACCELERATION] if self.acceleration else None, r[_SIGNALS] if self.signals else None,
                    route, r[_TYPE], light)

        return _columns(self.conn, ids, self.types, self.acceleration, self.signals, self.route, state,
                        self.lights is not None)


def read_traci_vehicles(conn, types=None, acceleration=True, signals=True, route=True, lights=None):
    """Every vehicle's state now, as columns in SUMO's conventions (Monitor.step_sumo takes them),
    read by one getter per variable and vehicle (TraciVehicleReader reads the same by subscription).
    `types` caches the vTypes between calls (a dict, filled here). With `route`, each vehicle's
    route from its current edge on (what the road prediction follows through junctions). `lights`
    (TraciVehicleReader's, its states read this step) adds next_signal and next_signal_distance."""
    v = conn.vehicle

    def state(vid):
        edges = list(v.getRoute(vid))[max(0, v.getRouteIndex(vid)):] if route else None
        light = (lights.next(edges, lambda: (v.getLaneID(vid), v.getLanePosition(vid)))
                 if lights is not None else None)
        return (v.getPosition(vid), v.getAngle(vid), v.getSpeed(vid), v.getLateralSpeed(vid),
                v.getAcceleration(vid) if acceleration else None, v.getSignals(vid) if signals else None,
                edges, v.getTypeID(vid), light)

    return _columns(conn, list(v.getIDList()), {} if types is None else types, acceleration, signals, route, state,
                    lights is not None)


def read_traci_persons(conn, types=None):
    """The persons on foot now (a person riding a vehicle is its vehicle's), as rows in SUMO's
    conventions: id, x, y, angle, speed and their vType's size and class (pedestrian, unless the
    type says otherwise), never equipped, as the C++ coupling reads them."""
    p = conn.person
    ids = [pid for pid in p.getIDList() if not p.getVehicle(pid)]
    return _person_rows(conn, ids, {} if types is None else types,
                        lambda pid: (p.getPosition(pid), p.getAngle(pid), p.getSpeed(pid), p.getTypeID(pid)))


def _person_rows(conn, ids, types, state):
    rows = []
    for pid in ids:
        (x, y), angle, speed, type_id = state(pid)
        t = types.get(type_id)
        if t is None:
            t = types[type_id] = _vehicle_type(conn, type_id)
        row = {"id": pid, "x": x, "y": y, "angle": angle, "speed": speed, "equipped": False}
        row.update(t)
        rows.append(row)
    return rows


# `state(vid)`: (position, angle, speed, lateral speed, acceleration, signals, route, type id,
# (next light's state, distance) or None), None where not read
def _columns(conn, ids, types, acceleration, signals, route, state, lights=False):
    cols = {k: [] for k in ("x", "y", "angle", "speed", "lateral_speed", "length", "width", "decel", "vehicle_class")}
    cols["id"] = ids
    if acceleration:
        cols["acceleration"] = []
    if signals:
        cols["signals"] = []
    if route:
        cols["route"] = []
    if lights:
        cols["next_signal"] = []
        cols["next_signal_distance"] = []
    masses = []
    for vid in ids:
        (x, y), angle, speed, lateral, accel, sig, edges, type_id, light = state(vid)
        if lights:
            cols["next_signal"].append(light[0])
            cols["next_signal_distance"].append(light[1])
        cols["x"].append(x)
        cols["y"].append(y)
        cols["angle"].append(angle)
        cols["speed"].append(speed)
        cols["lateral_speed"].append(lateral)
        if acceleration:
            cols["acceleration"].append(accel)
        if signals:
            cols["signals"].append(sig)
        if route:
            cols["route"].append(edges)
        t = types.get(type_id)
        if t is None:
            t = types[type_id] = _vehicle_type(conn, type_id)
        cols["length"].append(t["length"])
        cols["width"].append(t["width"])
        cols["decel"].append(t["decel"])
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

    TraciMonitor(conn, net=None, subscribe=None, **settings): conn is `traci`, a `traci.Connection`
    or `libsumo`; the road comes from `net` (a .net.xml) or, without it, from the lanes SUMO has
    loaded; `subscribe` as TraciVehicleReader's (None: subscriptions over TraCI, getters with
    libsumo); settings are Monitor's. take_finished(), take_conflicts(), take_events(), open_warnings(),
    alerts(), counters, settings, finish() as Monitor's (finish() without a time closes at SUMO's
    current time). It reads what the C++ coupling reads: the lights on the way (with the road
    prediction) and the persons on foot."""

    def __init__(self, conn, net=None, subscribe=None, **settings):
        # a clear word for a connection that is not one (None raised a raw AttributeError later)
        if conn is None or not hasattr(conn, "simulation") or not hasattr(conn, "vehicle"):
            raise TypeError("TraciMonitor needs a TraCI connection (traci, a traci.Connection or libsumo), got "
                            + type(conn).__name__)
        self.conn = conn
        self.monitor = Monitor(net, **settings) if net is not None else Monitor(lanes=read_traci_lanes(conn), **settings)
        in_effect = self.monitor.settings  # whatever spelling the caller used, and the defaults
        self.reader = TraciVehicleReader(conn, acceleration=in_effect["motion"] == "acceleration",
                                         signals=in_effect["check_road"], route=in_effect["prediction"] == "road",
                                         subscribe=subscribe, priority=in_effect["priority_rules"])

    def step(self):
        """Read every vehicle from SUMO and advance the monitor to SUMO's current time; call it
        after each simulationStep()."""
        self.monitor.step_sumo(self.conn.simulation.getTime(), self.reader.read())

    def finish(self, t=None):
        """Closes every open episode at time t (s); None: SUMO's current time."""
        self.monitor.finish(self.conn.simulation.getTime() if t is None else t)

    def take_finished(self):
        """Episodes that ended since the last call (WarningEpisode), in order of ending."""
        return self.monitor.take_finished()

    def take_conflicts(self):
        """Conflicts (Conflict: conflicts.csv's rows) settled since the last call."""
        return self.monitor.take_conflicts()

    def take_events(self):
        """Near misses and unsignalled crossings hindsight found since the last call (HindsightEvent)."""
        return self.monitor.take_events()

    def open_warnings(self):
        """Episodes still going on at the last step (WarningEpisode, open)."""
        return self.monitor.open_warnings()

    def alerts(self):
        """Each warned car's worst current threat at the last step (Alert: ego, kind, zone, ttc,
        safe_time, foe)."""
        return self.monitor.alerts()

    @property
    def counters(self):
        """The monitor's work counters, by name."""
        return self.monitor.counters

    @property
    def settings(self):
        """Every setting in effect, by its scenario key (as Monitor.settings)."""
        return self.monitor.settings
