#!/usr/bin/python3
"""Plot a trajectory CSV written by se3_interpolate (pose space) into a PNG.

usage: plot_trajectory.py TRAJECTORY.csv OUT.png [--title TITLE] [--bounds VMAX,WMAX,AMAX,ALPHAMAX]

Panels against time: position (x, y, z), rotation vector (the axis-angle vector of the
orientation relative to the first sample, rad), linear and angular speed (|v|, |ω|), and
linear and angular acceleration magnitudes (|a|, |α|). With --bounds (the request's
max_linear_velocity, max_angular_velocity, max_linear_acceleration, max_angular_acceleration;
0 = unbounded, not drawn) each bound is a dashed horizontal line in its rate's colour.
"""
import argparse
import csv
import math
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def read_csv(path):
    with open(path) as f:
        rows = list(csv.DictReader(f))
    if not rows:
        raise ValueError("%s: no samples" % path)
    required = ["t", "x", "y", "z", "qx", "qy", "qz", "qw", "vx", "vy", "vz", "wx", "wy", "wz",
                "ax", "ay", "az", "alx", "aly", "alz"]
    missing = [c for c in required if c not in rows[0]]
    if missing:
        raise ValueError("%s: missing columns %s (expected se3_interpolate's pose CSV)" % (path, missing))
    return {c: [float(r[c]) for r in rows] for c in required}


def quat_mul(a, b):
    ax, ay, az, aw = a
    bx, by, bz, bw = b
    return (aw * bx + ax * bw + ay * bz - az * by,
            aw * by - ax * bz + ay * bw + az * bx,
            aw * bz + ax * by - ay * bx + az * bw,
            aw * bw - ax * bx - ay * by - az * bz)


def rotation_vector(q):
    x, y, z, w = q
    if w < 0:
        x, y, z, w = -x, -y, -z, -w
    n = math.sqrt(x * x + y * y + z * z)
    if n < 1e-15:
        return (2 * x, 2 * y, 2 * z)
    angle = 2 * math.atan2(n, w)
    return (angle * x / n, angle * y / n, angle * z / n)


def norm(xs, ys, zs):
    return [math.sqrt(a * a + b * b + c * c) for a, b, c in zip(xs, ys, zs)]


def parse_bounds(text):
    """Four comma-separated numbers >= 0 (0: no line)."""
    try:
        values = [float(x) for x in text.split(",")]
    except ValueError:
        raise argparse.ArgumentTypeError("expected VMAX,WMAX,AMAX,ALPHAMAX (numbers), got '%s'" % text)
    if len(values) != 4 or any(not math.isfinite(v) or v < 0 for v in values):
        raise argparse.ArgumentTypeError("expected four finite numbers >= 0 (0: unbounded), got '%s'" % text)
    return values


def plot_rate(axis, t, values, label, bound):
    line, = axis.plot(t, values, label=label)
    if bound > 0:
        axis.axhline(bound, color=line.get_color(), linestyle="--", linewidth=1, label="bound %g" % bound)


def main(argv):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("csv")
    parser.add_argument("png")
    parser.add_argument("--title", default="")
    parser.add_argument("--bounds", type=parse_bounds, default=[0.0, 0.0, 0.0, 0.0],
                        help="VMAX,WMAX,AMAX,ALPHAMAX drawn as dashed lines (0: none)")
    args = parser.parse_args(argv)
    try:
        d = read_csv(args.csv)
    except (OSError, ValueError) as e:
        print("plot_trajectory: error: %s" % e, file=sys.stderr)
        return 2
    t = d["t"]
    q0 = (d["qx"][0], d["qy"][0], d["qz"][0], d["qw"][0])
    q0_inv = (-q0[0], -q0[1], -q0[2], q0[3])
    rv = [rotation_vector(quat_mul(q, q0_inv)) for q in zip(d["qx"], d["qy"], d["qz"], d["qw"])]

    fig, ax = plt.subplots(4, 1, figsize=(9, 11), sharex=True)
    for c in "xyz":
        ax[0].plot(t, d[c], label=c)
    ax[0].set_ylabel("position [m]")
    for i, c in enumerate("xyz"):
        ax[1].plot(t, [r[i] for r in rv], label="r" + c)
    ax[1].set_ylabel("rotation vector [rad]\n(relative to start)")
    vmax, wmax, amax, alphamax = args.bounds
    plot_rate(ax[2], t, norm(d["vx"], d["vy"], d["vz"]), "|v| [m/s]", vmax)
    plot_rate(ax[2], t, norm(d["wx"], d["wy"], d["wz"]), "|ω| [rad/s]", wmax)
    ax[2].set_ylabel("speed")
    plot_rate(ax[3], t, norm(d["ax"], d["ay"], d["az"]), "|a| [m/s²]", amax)
    plot_rate(ax[3], t, norm(d["alx"], d["aly"], d["alz"]), "|α| [rad/s²]", alphamax)
    ax[3].set_ylabel("acceleration")
    ax[3].set_xlabel("t [s]")
    for a in ax:
        a.grid(True, alpha=0.3)
        a.legend(loc="upper right", fontsize=8)
    if args.title:
        fig.suptitle(args.title)
    fig.tight_layout()
    fig.savefig(args.png, dpi=90)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
