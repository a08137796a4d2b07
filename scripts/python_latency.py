#!/usr/bin/python3
"""Wall time of the Python module on the request of scripts/service_latency.sh.

N waypoints on the walk of bench/service_latency.cpp (`interpolating`, double_geodesic), M samples:
  - generate() into numpy arrays (the planner and the arrays);
  - the same request with 2 samples, and the difference: the C++ sampling of M samples inside
    generate() (kinematics, quaternion signs, the copies into the arrays);
  - Curve.evaluate() of the request's untimed curve at the same M times.
Prints the median and minimum of R repetitions of each, in seconds. Run it after `source
scripts/setup.bash` (docs/python.md "Performance").

Usage: python_latency.py [--waypoints N] [--samples M] [--repetitions R]
"""
import argparse
import time

import numpy as np

import se3_interpolation as s


def walk(n):
    """The waypoints of bench/service_latency.cpp as an (n, 7) array (q = q_z(yaw) q_x(roll))."""
    i = np.arange(n, dtype=float)
    yaw, roll = 0.4 * i, 0.3 * np.sin(0.7 * i)
    cy, sy, cr, sr = np.cos(0.5 * yaw), np.sin(0.5 * yaw), np.cos(0.5 * roll), np.sin(0.5 * roll)
    return np.stack([0.3 * i, np.sin(0.5 * i), 0.2 * np.cos(0.3 * i), cy * sr, sy * sr, sy * cr, cy * cr], axis=1)


def timed(function, repetitions):
    """(median, minimum) wall time of function() over the repetitions."""
    times = []
    for _ in range(repetitions):
        start = time.perf_counter()
        function()
        times.append(time.perf_counter() - start)
    times.sort()
    return times[len(times) // 2], times[0]


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--waypoints", type=int, default=1000)
    parser.add_argument("--samples", type=int, default=100000)
    parser.add_argument("--repetitions", type=int, default=5)
    args = parser.parse_args()
    request = dict(waypoints=walk(args.waypoints), curve="interpolating", geometry="double_geodesic")
    curve = s.interpolating(request["waypoints"])
    times = s.generate(request, sample_count=args.samples).t
    rows = [
        ("generate(), %d samples into numpy" % args.samples,
         timed(lambda: s.generate(request, sample_count=args.samples), args.repetitions)),
        ("generate(), 2 samples", timed(lambda: s.generate(request, sample_count=2), args.repetitions)),
        ("Curve.evaluate(), %d times" % len(times), timed(lambda: curve.evaluate(times), args.repetitions)),
    ]
    for name, (median, minimum) in rows:
        print("%-45s median %.4f s, min %.4f s" % (name, median, minimum))
    sampling = rows[0][1][0] - rows[1][1][0]
    print("%-45s %.4f s (the medians' difference); evaluate / sampling = %.2f" %
          ("C++ sampling inside generate()", sampling, rows[2][1][0] / sampling))


if __name__ == "__main__":
    main()
