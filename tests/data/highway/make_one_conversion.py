#!/usr/bin/env python3
"""Writes one_conversion.csv: SUMO records (what TraCI, libsumo and an FCD trace report) for six
vehicles over 30 s at 0.5 s steps on lanedrop.net.xml's edge `main`, chosen to exercise every
part of the conversion: a follower closing on a braking leader (brake light, bit 3), a sublane
drift to the right with its blinker (lateral speed, posLat, a heading turned by the drift), a
trailer braking behind a bicycle with hazard lights (bit 2), a late entry that leaves early, and
vTypes with and without their attributes (one_conversion.rou.xml). Numbers are written in full
(repr) so every reader parses the same doubles; the lateral steps are binary fractions."""
import math
from pathlib import Path

DT = 0.5
LANES = {"main_0": -8.0, "main_1": -4.8, "main_2": -1.6}


def brake(x0, v0, t0, a, v1, t):
    """Position, speed, acceleration of a car at v0 from x0 that brakes at `a` from t0 to v1."""
    if t <= t0:
        return x0 + v0 * t, v0, 0.0
    tb = (v0 - v1) / -a
    x = x0 + v0 * t0
    if t <= t0 + tb:
        s = t - t0
        return x + v0 * s + 0.5 * a * s * s, v0 + a * s, a
    return x + v0 * tb + 0.5 * a * tb * tb + v1 * (t - t0 - tb), v1, 0.0


def rows():
    for k in range(61):
        t = k * DT
        # lead: brakes at 4 m/s^2 from t = 5 s to 4 m/s, brake light on while it brakes
        x, v, a = brake(300.0, 20.0, 5.0, -4.0, 4.0, t)
        yield t, "lead", "car", "main_1", x, LANES["main_1"], 90.0, v, 0.0, 0.0, a, 8 if a < 0 else 0
        x, v, a = brake(220.0, 28.0, 6.0, -7.0, 4.0, t)
        yield t, "follow", "car", "main_1", x, LANES["main_1"], 90.0, v, 0.0, 0.0, a, 8 if a < 0 else 0
        # drift: 0.5 m/s to the right from t = 2 to 4.5 s (posLat 0 -> -1.25), right blinker meanwhile;
        # its lateral speed and angle are those of the step that ends at t
        pos_lat = -0.5 * min(max(t - 2.0, 0.0), 2.5)
        lat = -0.5 if 2.0 < t <= 4.5 else 0.0
        angle = 90.0 + math.degrees(math.atan2(-lat, 25.0))
        yield (t, "drift", "anon", "main_2", 250.0 + 25.0 * t, LANES["main_2"] + pos_lat, angle, 25.0, lat, pos_lat,
               0.0, 1 if 1.0 <= t <= 4.5 else 0)
        x, v, a = brake(100.0, 22.0, 21.0, -3.0, 6.0, t)
        yield t, "trailer", "trailer", "main_0", x, LANES["main_0"], 90.0, v, 0.0, 0.0, a, 0
        yield t, "bike", "bike", "main_0", 500.0 + 6.0 * t, LANES["main_0"], 90.0, 6.0, 0.0, 0.0, 0.0, 4
        if 10.0 <= t <= 20.0:
            s = t - 10.0
            yield (t, "late", "car", "main_2", 200.0 + 20.0 * s + 0.5 * s * s, LANES["main_2"], 90.0, 20.0 + s, 0.0, 0.0,
                   1.0, 2 if t >= 18.0 else 0)


def main():
    out = Path(__file__).with_name("one_conversion.csv")
    with open(out, "w") as f:
        f.write("time,id,type,lane,x,y,angle,speed,lateral_speed,pos_lat,acceleration,signals\n")
        for r in rows():
            f.write(",".join(repr(float(c)) if isinstance(c, float) else str(c) for c in r) + "\n")


if __name__ == "__main__":
    main()
