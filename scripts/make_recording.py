#!/usr/bin/python3
"""Write a synthetic noisy pose recording as CSV (t,x,y,z,qx,qy,qz,qw), the input of
`se3_interpolate --waypoints` and of curve fit: the slow tool motion of bench/recording.h
(positions of tens of cm, rotations up to 0.8 rad, frequencies below 0.1 Hz) with Gaussian noise
of NOISE_MM per axis and NOISE_DEG per rotation axis, OUTLIERS poses displaced by OUTLIER_M in a
random direction, and the quaternion's sign flipped on a random half of the poses (both signs are
the same rotation, as trackers report them). Fixed seed: the same file every run.

usage: make_recording.py [OUT.csv] [--duration S] [--rate HZ] [--noise-mm MM] [--noise-deg DEG]
                         [--outliers N] [--outlier-m M] [--seed N]
(docs/examples/fit_recording.csv is `make_recording.py docs/examples/fit_recording.csv --rate 50`)
"""
import argparse
import math
import random
import sys


def rotation(w):
    """Unit quaternion (x, y, z, w) of the rotation vector w (rad)."""
    angle = math.sqrt(sum(c * c for c in w))
    if angle < 1e-12:
        return (0.5 * w[0], 0.5 * w[1], 0.5 * w[2], 1.0)
    s = math.sin(angle / 2) / angle
    return (w[0] * s, w[1] * s, w[2] * s, math.cos(angle / 2))


def multiply(a, b):
    """Quaternion product a b, (x, y, z, w) order."""
    ax, ay, az, aw = a
    bx, by, bz, bw = b
    return (aw * bx + ax * bw + ay * bz - az * by,
            aw * by - ax * bz + ay * bw + az * bx,
            aw * bz + ax * by - ay * bx + az * bw,
            aw * bw - ax * bx - ay * by - az * bz)


def truth(t):
    """The noiseless motion at t (s): position (m) and rotation vector (rad), as bench/recording.h."""
    two_pi = 2 * math.pi
    p = (0.3 * math.sin(two_pi * 0.05 * t), 0.2 * math.cos(two_pi * 0.08 * t),
         0.1 * math.sin(two_pi * 0.03 * t + 1.0))
    w = (0.5 * math.sin(two_pi * 0.04 * t), 0.3 * math.cos(two_pi * 0.07 * t),
         0.8 * math.sin(two_pi * 0.02 * t))
    return p, w


def recording(duration, rate, noise_m, noise_rad, outliers, outlier_m, seed):
    """Rows (t, x, y, z, qx, qy, qz, qw) of the recording."""
    rng = random.Random(seed)
    count = int(round(duration * rate)) + 1
    displaced = set(rng.sample(range(1, count - 1), min(outliers, max(0, count - 2))))
    rows = []
    for i in range(count):
        t = i / rate
        p, w = truth(t)
        p = [c + noise_m * rng.gauss(0, 1) for c in p]
        q = multiply(rotation(w), rotation([noise_rad * rng.gauss(0, 1) for _ in range(3)]))
        if i in displaced:
            d = [rng.gauss(0, 1) for _ in range(3)]
            n = math.sqrt(sum(c * c for c in d))
            p = [c + outlier_m * e / n for c, e in zip(p, d)]
        if rng.random() < 0.5:
            q = tuple(-c for c in q)
        rows.append((t, *p, *q))
    return rows


def main(argv):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("out", nargs="?", default="-", help="CSV file (default: standard output)")
    parser.add_argument("--duration", type=float, default=10.0, help="s (default 10)")
    parser.add_argument("--rate", type=float, default=100.0, help="Hz (default 100)")
    parser.add_argument("--noise-mm", type=float, default=1.0, help="position noise per axis, mm (default 1)")
    parser.add_argument("--noise-deg", type=float, default=0.5, help="rotation noise per axis, deg (default 0.5)")
    parser.add_argument("--outliers", type=int, default=5, help="poses displaced by --outlier-m (default 5)")
    parser.add_argument("--outlier-m", type=float, default=0.1, help="outlier displacement, m (default 0.1)")
    parser.add_argument("--seed", type=int, default=30, help="random seed (default 30)")
    a = parser.parse_args(argv)
    if a.duration <= 0 or a.rate <= 0 or a.noise_mm < 0 or a.noise_deg < 0 or a.outliers < 0:
        parser.error("--duration and --rate must be positive, the noise and --outliers not negative")
    rows = recording(a.duration, a.rate, a.noise_mm / 1000, math.radians(a.noise_deg), a.outliers, a.outlier_m,
                     a.seed)
    text = "t,x,y,z,qx,qy,qz,qw\n" + "".join(",".join(repr(v) for v in r) + "\n" for r in rows)
    if a.out == "-":
        sys.stdout.write(text)
    else:
        with open(a.out, "w") as f:
            f.write(text)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
