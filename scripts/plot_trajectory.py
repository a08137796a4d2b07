#!/usr/bin/python3
"""Plot a trajectory CSV written by se3_interpolate (pose space) into a PNG.

usage: plot_trajectory.py [CSV|-] [OUT.png] [--figures FIGURES.txt] [--max-linear-velocity V] ...
                          [--max-linear-jerk J] [--max-angular-jerk J]

CSV is the CLI's output file, or `-` / nothing for standard input, so
`rosrun se3_interpolation se3_interpolate REQUEST.yaml | scripts/plot_trajectory.py - OUT.png` works.
OUT.png defaults to trajectory.png (CSV from stdin) or the CSV's name with .png.

Two columns, linear quantities left and angular right, each panel with its own unit, against
time t [s]: position x, y, z [m] | rotation vector [rad]; speed |v| [m/s] | |w| [rad/s];
acceleration |a| [m/s^2] | |dw/dt| [rad/s^2]; jerk |d3p/dt3| [m/s^3] | |d2w/dt2| [rad/s^3].
The jerks are finite differences of the CSV's accelerations (columns ax.. and alx..) between
consecutive samples, drawn at the middle of each interval: where the acceleration jumps (a
time-optimal profile) the jerk shows as a spike of height jump / sample interval, so its height
depends on the sampling. The rotation vector is that of R(t) R(0)^T
(world frame, relative to the first sample), unwrapped: past an angle of pi it continues along
the same axis (angles beyond pi) instead of jumping to the opposite vector.

--figures takes the CLI's standard error (`2>FIGURES.txt`): its `waypoint_times` are drawn as
vertical dotted lines with the waypoint index, a constant-speed window (`constant_speed_start`,
`constant_speed_end` of timing constant_speed) is shaded green, and the figures go into the title. The
--max-* options (the request's field names, --max-linear-jerk and --max-angular-jerk included)
draw bounds as dashed horizontal lines.

Runs with Debian's /usr/bin/python3 (the shebang): run it as scripts/plot_trajectory.py; a
`python3` from pyenv or a virtualenv may lack matplotlib.
"""
import argparse
import csv
import math
import os
import sys

try:
    import matplotlib
except ImportError:
    sys.exit("plot_trajectory: error: %s has no matplotlib; run the script as scripts/plot_trajectory.py "
             "(its shebang is Debian's /usr/bin/python3, with python3-matplotlib)" % sys.executable)

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

COLUMNS = ["t", "x", "y", "z", "qx", "qy", "qz", "qw", "vx", "vy", "vz", "wx", "wy", "wz",
           "ax", "ay", "az", "alx", "aly", "alz"]


def read_columns(stream, name, columns, expected):
    """The named columns of a CSV (found by name, in any order) as lists of floats; `expected`
    says what the file should be in the error of a missing column."""
    rows = list(csv.DictReader(stream))
    if not rows:
        raise ValueError("%s: no samples" % name)
    missing = [c for c in columns if c not in rows[0]]
    if missing:
        raise ValueError("%s: missing columns %s (expected %s)" % (name, missing, expected))
    try:
        return {c: [float(r[c]) for r in rows] for c in columns}
    except (TypeError, ValueError):
        raise ValueError("%s: a value is not a number" % name)


def read_csv(stream, name):
    return read_columns(stream, name, COLUMNS, "se3_interpolate's pose CSV")


def read_figures(path):
    """`name: value` lines of the CLI's standard error; waypoint_times as a list."""
    figures = {}
    with open(path) as f:
        for line in f:
            name, sep, value = line.partition(": ")
            if not sep:
                continue
            value = value.strip()
            if name == "waypoint_times":
                figures[name] = [float(v) for v in value.split(",") if v.strip()]
            else:
                try:
                    figures[name] = float(value)
                except ValueError:
                    pass
    return figures


def constant_speed_window(figures):
    """(start, end) of the constant-speed window the figures report, or None."""
    start, end = figures.get("constant_speed_start"), figures.get("constant_speed_end")
    return (start, end) if start is not None and end is not None and end > start else None


def quat_mul(a, b):
    ax, ay, az, aw = a
    bx, by, bz, bw = b
    return (aw * bx + ax * bw + ay * bz - az * by,
            aw * by - ax * bz + ay * bw + az * bx,
            aw * bz + ax * by - ay * bx + az * bw,
            aw * bw - ax * bx - ay * by - az * bz)


def rotation_vector(q):
    """Principal rotation vector (angle in [0, pi]) of the unit quaternion q = (x, y, z, w)."""
    x, y, z, w = q
    if w < 0:
        x, y, z, w = -x, -y, -z, -w
    n = math.sqrt(x * x + y * y + z * z)
    if n < 1e-15:
        return (2 * x, 2 * y, 2 * z)
    angle = 2 * math.atan2(n, w)
    return (angle * x / n, angle * y / n, angle * z / n)


def nearest_branch(r, ref):
    """Of the rotation vectors equivalent to r = angle * axis, (angle + 2 pi k) * axis, the one
    nearest to ref: the integer k for which angle + 2 pi k is nearest to ref . axis
    (|(angle + 2 pi k) axis - ref|^2 is a parabola in angle + 2 pi k with its minimum there). At a
    whole number of turns (angle 0) the axis is ref's."""
    angle = math.sqrt(sum(c * c for c in r))
    if angle < 1e-12:
        prev = math.sqrt(sum(c * c for c in ref))
        if prev < 1e-12:
            return r
        k = round(prev / (2 * math.pi))
        return [2 * math.pi * k * c / prev for c in ref]
    axis = [c / angle for c in r]
    along = sum(a * p for a, p in zip(axis, ref))
    k = round((along - angle) / (2 * math.pi))
    return [(angle + 2 * math.pi * k) * a for a in axis]


def unwrap(vectors):
    """Rotation vectors made continuous: each on the branch nearest to the previous sample's
    vector (nearest_branch)."""
    out = []
    for r in vectors:
        out.append(r if not out else nearest_branch(r, out[-1]))
    return out


def norm(xs, ys, zs):
    return [math.sqrt(a * a + b * b + c * c) for a, b, c in zip(xs, ys, zs)]


def jerk(t, xs, ys, zs):
    """(interval midpoints, |difference quotient|) of a sampled vector: the magnitude of its time
    derivative between consecutive samples, e.g. the jerk from the accelerations."""
    mid, mags = [], []
    for k in range(1, len(t)):
        h = t[k] - t[k - 1]
        if h <= 0:
            continue
        mid.append(0.5 * (t[k] + t[k - 1]))
        mags.append(math.sqrt((xs[k] - xs[k - 1]) ** 2 + (ys[k] - ys[k - 1]) ** 2 + (zs[k] - zs[k - 1]) ** 2) / h)
    return mid, mags


def positive(text):
    v = float(text)
    if not (v > 0 and math.isfinite(v)):
        raise argparse.ArgumentTypeError("expected a positive number, got %s" % text)
    return v


def main(argv):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("csv", nargs="?", default="-", help="se3_interpolate's CSV, or - (default) for stdin")
    parser.add_argument("png", nargs="?", help="output PNG (default: trajectory.png, or CSV name with .png)")
    parser.add_argument("--title", default="")
    parser.add_argument("--figures", metavar="FILE",
                        help="se3_interpolate's standard error: marks its waypoint_times")
    parser.add_argument("--max-linear-velocity", type=positive, metavar="M_PER_S")
    parser.add_argument("--max-angular-velocity", type=positive, metavar="RAD_PER_S")
    parser.add_argument("--max-linear-acceleration", type=positive, metavar="M_PER_S2")
    parser.add_argument("--max-angular-acceleration", type=positive, metavar="RAD_PER_S2")
    parser.add_argument("--max-linear-jerk", type=positive, metavar="M_PER_S3")
    parser.add_argument("--max-angular-jerk", type=positive, metavar="RAD_PER_S3")
    args = parser.parse_args(argv)
    if args.png is None:
        args.png = "trajectory.png" if args.csv == "-" else os.path.splitext(args.csv)[0] + ".png"
    try:
        if args.csv == "-":
            d = read_csv(sys.stdin, "standard input")
        else:
            with open(args.csv) as f:
                d = read_csv(f, args.csv)
        figures = read_figures(args.figures) if args.figures else {}
    except (OSError, ValueError) as e:
        print("plot_trajectory: error: %s" % e, file=sys.stderr)
        return 2
    t = d["t"]
    q0 = (d["qx"][0], d["qy"][0], d["qz"][0], d["qw"][0])
    q0_inv = (-q0[0], -q0[1], -q0[2], q0[3])
    rv = unwrap([rotation_vector(quat_mul(q, q0_inv)) for q in zip(d["qx"], d["qy"], d["qz"], d["qw"])])

    fig, ax = plt.subplots(4, 2, figsize=(12, 12), sharex=True)
    for c in "xyz":
        ax[0][0].plot(t, d[c], label=c)
    ax[0][0].set_ylabel("position [m]")
    for i, c in enumerate("xyz"):
        ax[0][1].plot(t, [r[i] for r in rv], label="r" + c)
    ax[0][1].set_ylabel("rotation vector [rad]\n(of R(t) R(0)^T, unwrapped)")
    ax[1][0].plot(t, norm(d["vx"], d["vy"], d["vz"]), label="|v|", color="C0")
    ax[1][0].set_ylabel("linear speed |v| [m/s]")
    ax[1][1].plot(t, norm(d["wx"], d["wy"], d["wz"]), label="|w|", color="C1")
    ax[1][1].set_ylabel("angular speed |w| [rad/s]")
    ax[2][0].plot(t, norm(d["ax"], d["ay"], d["az"]), label="|a|", color="C0")
    ax[2][0].set_ylabel("linear acceleration |a| [m/s$^2$]")
    ax[2][1].plot(t, norm(d["alx"], d["aly"], d["alz"]), label="|dw/dt|", color="C1")
    ax[2][1].set_ylabel("angular acceleration |dw/dt| [rad/s$^2$]")
    ax[3][0].plot(*jerk(t, d["ax"], d["ay"], d["az"]), label="|da/dt|", color="C0")
    ax[3][0].set_ylabel("linear jerk |d$^3$p/dt$^3$| [m/s$^3$]\n(differences of a)")
    ax[3][1].plot(*jerk(t, d["alx"], d["aly"], d["alz"]), label="|d2w/dt2|", color="C1")
    ax[3][1].set_ylabel("angular jerk |d$^2$w/dt$^2$| [rad/s$^3$]\n(differences of dw/dt)")
    # Magnitudes start at 0; rounding noise (1e-15 on a geodesic) is not blown up to full height.
    for a in (ax[1][0], ax[1][1], ax[2][0], ax[2][1], ax[3][0], ax[3][1]):
        top = max((max(line.get_ydata()) for line in a.get_lines() if len(line.get_ydata())), default=0.0)
        a.set_ylim(0, 1.08 * top if top > 1e-9 else 1)
    bounds = [(ax[1][0], args.max_linear_velocity, "max_linear_velocity"),
              (ax[1][1], args.max_angular_velocity, "max_angular_velocity"),
              (ax[2][0], args.max_linear_acceleration, "max_linear_acceleration"),
              (ax[2][1], args.max_angular_acceleration, "max_angular_acceleration"),
              (ax[3][0], args.max_linear_jerk, "max_linear_jerk"),
              (ax[3][1], args.max_angular_jerk, "max_angular_jerk")]
    for a, bound, name in bounds:
        if bound is not None:
            a.axhline(bound, color="red", linestyle="--", linewidth=1, label="%s %g" % (name, bound))
            a.set_ylim(0, max(a.get_ylim()[1], 1.08 * bound))
    for i, tw in enumerate(figures.get("waypoint_times", [])):
        for row in ax:
            for a in row:
                a.axvline(tw, color="grey", linestyle=":", linewidth=1)
        for a in ax[0]:
            a.annotate(str(i), xy=(tw, 1.0), xycoords=("data", "axes fraction"), xytext=(0, 2),
                       textcoords="offset points", fontsize=8, color="grey", ha="center", va="bottom")
    window = constant_speed_window(figures)
    if window:
        for row in ax:
            for a in row:
                a.axvspan(window[0], window[1], color="green", alpha=0.08,
                          label="constant speed" if a is ax[1][0] else None)
    for row in ax:
        for a in row:
            a.grid(True, alpha=0.3)
            a.legend(loc="best", fontsize=8)
    for a in ax[-1]:
        a.set_xlabel("t [s]")
    title = args.title
    if figures:
        parts = ["%s %.4g" % (k, figures[k]) for k in ("duration", "length", "rotation_length", "energy")
                 if k in figures]
        if "waypoint_times" in figures:
            parts.append("dotted: waypoint times (index above)")
        title = (title + "\n" if title else "") + ", ".join(parts)
    if title:
        fig.suptitle(title)
    fig.tight_layout()
    fig.savefig(args.png, dpi=80)
    print("plot_trajectory: wrote %s" % args.png)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
