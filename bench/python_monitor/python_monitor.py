#!/usr/bin/python3
"""stsim.TraciMonitor against the reads it needs, side by side in one run.

    PYTHONPATH=build/python bench/python_monitor/python_monitor.py [--steps 1000] [--rounds 2]
        [--config /usr/share/sumo/tools/game/highway.sumocfg] [--backend traci,libsumo]

For each backend (a TraCI socket to a sumo process, or libsumo in this process) and each row, SUMO
runs the config's first `steps` steps from a fresh start; the table gives the wall time of the loop
(SUMO's steps included) and its ratio to the subscription read of the same backend:

    sumo             the steps alone
    read subscribed  the steps and, after each, every vehicle's position, angle, speed, lateral
                     speed, type, signals, route id and route index by subscription (one
                     subscribe per vehicle, then getAllSubscriptionResults): the variables
                     TraciMonitor needs, read the fastest way TraCI offers
    read getters     the same variables by one getter per variable and vehicle
    monitor          stsim.TraciMonitor (the five-circle detector, road prediction, hindsight):
                     its reads (the faster way per backend) and the monitor's work
    monitor getters  TraciMonitor(subscribe=False)

The minimum over `rounds` alternating rounds is printed. The issue's target: monitor <= 2x read
subscribed on the TraCI backend."""
import argparse
import os
import sys
import time

sys.path.append("/usr/share/sumo/tools")
os.environ.setdefault("SUMO_HOME", "/usr/share/sumo")

import stsim  # noqa: E402

VARIABLES = [0x42, 0x43, 0x40, 0x32, 0x4f, 0x5b, 0x53, 0x69]  # position ... route index


def sumo_args(config):
    return ["sumo", "-c", config, "--no-step-log", "true", "--duration-log.disable", "true",
            "--no-warnings", "true", "--collision.action", "warn"]


def run(conn, config, steps, row):
    conn.start(sumo_args(config))
    try:
        v = conn.vehicle
        monitor = None
        if row == "monitor":
            monitor = stsim.TraciMonitor(conn, detector="five")
        elif row == "monitor getters":
            monitor = stsim.TraciMonitor(conn, detector="five", subscribe=False)
        vehicle_steps = 0
        start = time.perf_counter()
        for _ in range(steps):
            conn.simulationStep()
            if row == "read subscribed":
                ids = v.getIDList()
                results = v.getAllSubscriptionResults()
                for vid in ids:
                    if vid not in results:
                        v.subscribe(vid, VARIABLES)
                results = v.getAllSubscriptionResults()
                vehicle_steps += len(results)
            elif row == "read getters":
                for vid in v.getIDList():
                    v.getPosition(vid), v.getAngle(vid), v.getSpeed(vid), v.getLateralSpeed(vid)
                    v.getTypeID(vid), v.getSignals(vid), v.getRouteID(vid), v.getRouteIndex(vid)
                    vehicle_steps += 1
            elif monitor is not None:
                monitor.step()
            else:
                vehicle_steps += v.getIDCount()
        if monitor is not None:
            monitor.finish()
            vehicle_steps = monitor.counters.get("vehicle_steps", 0)
        wall = time.perf_counter() - start
        warnings = len(monitor.take_finished()) if monitor is not None else None
    finally:
        conn.close()
    return wall, vehicle_steps, warnings


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--steps", type=int, default=1000)
    ap.add_argument("--rounds", type=int, default=2)
    ap.add_argument("--config", default="/usr/share/sumo/tools/game/highway.sumocfg")
    ap.add_argument("--backend", default="traci,libsumo")
    a = ap.parse_args()
    if a.steps < 1 or a.rounds < 1:
        ap.error("--steps and --rounds must be at least 1")
    if not os.path.exists(a.config):
        ap.error(f"--config {a.config}: no such file")
    rows = ["sumo", "read subscribed", "read getters", "monitor", "monitor getters"]
    print(f"# {a.config}, {a.steps} steps, min of {a.rounds} rounds")
    print(f"{'backend':8} {'row':16} {'wall s':>8} {'/ read subscribed':>18} {'warnings':>9}")
    for backend in a.backend.split(","):
        if backend == "traci":
            import traci as conn
        elif backend == "libsumo":
            import libsumo as conn
        else:
            ap.error(f"--backend: unknown backend '{backend}' (traci, libsumo)")
        best = {}
        for _ in range(a.rounds):
            for row in rows:
                wall, _, warnings = run(conn, a.config, a.steps, row)
                if row not in best or wall < best[row][0]:
                    best[row] = (wall, warnings)
        base = best["read subscribed"][0]
        for row in rows:
            wall, warnings = best[row]
            print(f"{backend:8} {row:16} {wall:8.3f} {wall / base:18.2f} {'' if warnings is None else warnings:>9}")


if __name__ == "__main__":
    main()
