#!/usr/bin/env python3
"""Check a se3_interpolate CSV against a robot controller's Cartesian limits, seen from poses only.

usage: check_controller_limits.py CSV (--franka | --max-linear-velocity V ...) [--rate HZ]

A controller such as libfranka's Cartesian pose interface receives one pose per tick and
differentiates the poses itself. This script does the same with the CSV's POSES (columns x, y, z,
qx, qy, qz, qw; the CSV's velocity and acceleration columns are not used), by backward finite
differences at the controller period dt = 1/--rate (default 1000 Hz):

  translation  v_k = (p_k - p_{k-1}) / dt,        a_k = (v_k - v_{k-1}) / dt,  j_k = (a_k - a_{k-1}) / dt
  rotation     w_k = log(R_k R_{k-1}^T) / dt,     dw_k = (w_k - w_{k-1}) / dt, ddw_k = (dw_k - dw_{k-1}) / dt

w_k is the rotation vector of the step in the base (world) frame: log(R_k R_{k-1}^T) =
R_{k-1} log(R_{k-1}^T R_k), what libfranka 0.9's limitRate computes from two poses. The norms
|v|, |a|, |j|, |w|, |dw|, |ddw| are compared with the limits at every tick k.

Sampling: NO resampling is done. The samples must already be on the controller's grid:
t_k = t_0 + k dt (to 1e-6 dt), which is what se3_interpolate writes with `sample_period: 0.001`
in the request, except that the last interval may be shorter (the CLI's last sample is at the
duration itself): that last pose is taken as commanded at the next tick, t_{N-2} + dt. Any other
sampling is refused with exit status 2 (resample with the CLI, not here).

Rest: the controller holds the pose before the first sample and after the last one, so the
differences are also taken across those joins (three held ticks on each side; violations there are
reported at the held ticks' times, e.g. t_last + 1 ms). Besides, the motion must start and end at
rest: the velocity over the first (last) interval and the acceleration over the first (last) two
intervals must be within --rest-velocity-tolerance and --rest-acceleration-tolerance (same value
for m/s and rad/s, m/s^2 and rad/s^2); a motion that does not is reported as a `rest` violation.

Limits: --franka sets libfranka 0.9's nominal Cartesian limits (include/franka/rate_limiting.h of
libfranka 0.8.0 to 0.9.2: 2.0 m/s, 13 m/s^2, 6500 m/s^3 in translation; 2.5 rad/s, 25 rad/s^2,
12500 rad/s^3 in rotation; libfranka 0.4 to 0.7 had 1.7 m/s, 0.10+ (FR3) has other values). The
header's constants are these minus margins (kLimitEps = 1e-3, a velocity reserve for 3 lost packets,
so 1.960 m/s and 2.424 rad/s), and the pose interface scales the rotational ones by 0.99: the
nominal values here are the upper end. Each limit can be given or overridden with --max-*; a
quantity without a limit is not checked (its peak is still printed).

Output: one line per violation, consecutive ticks of one quantity grouped into one line (first
time, quantity, first value, limit, time interval, number of ticks, peak and its time), sorted by
first time, then a summary line with the peaks. Exit status: 0 within the limits, 1 when a limit
(or the rest condition) is violated, 2 on bad input (missing file, bad header, non-uniform
sampling, a malformed or non-finite value: the message names the line).

Example:
  se3_interpolate /tmp/jerk_limited_1khz.yaml -o /tmp/jl.csv   # request with sample_period: 0.001
  scripts/check_controller_limits.py /tmp/jl.csv --franka
Needs numpy. The shebang is `/usr/bin/env python3`: a pyenv or virtualenv python3 first in PATH
may lack numpy (the script then says so and exits 2); Debian's /usr/bin/python3 has it, so run
`/usr/bin/python3 scripts/check_controller_limits.py ...` or put /usr/bin first in PATH.
"""
import argparse
import csv
import math
import sys

try:
    import numpy as np
except ImportError:
    print("check_controller_limits: error: %s has no numpy; run it with a python3 that has it, e.g. "
          "/usr/bin/python3 scripts/check_controller_limits.py ... (Debian's python3-numpy), or put /usr/bin "
          "first in PATH" % sys.executable, file=sys.stderr)
    sys.exit(2)

COLUMNS = ["t", "x", "y", "z", "qx", "qy", "qz", "qw", "vx", "vy", "vz", "wx", "wy", "wz",
           "ax", "ay", "az", "alx", "aly", "alz"]

# libfranka 0.9 (its header franka/rate_limiting.h, tags 0.8.0-0.9.2), nominal values.
FRANKA = {"linear_velocity": 2.0, "linear_acceleration": 13.0, "linear_jerk": 6500.0,
          "angular_velocity": 2.5, "angular_acceleration": 25.0, "angular_jerk": 12500.0}

# (key, printed name, unit), in report order.
QUANTITIES = [("linear_velocity", "linear velocity", "m/s"),
              ("linear_acceleration", "linear acceleration", "m/s^2"),
              ("linear_jerk", "linear jerk", "m/s^3"),
              ("angular_velocity", "angular velocity", "rad/s"),
              ("angular_acceleration", "angular acceleration", "rad/s^2"),
              ("angular_jerk", "angular jerk", "rad/s^3")]

HELD_TICKS = 3  # enough for the jerk across a join to be computed from held poses only


class BadInput(Exception):
    pass


def read_csv(path):
    """(t, p, q) arrays of the CSV, checked: header, field count, finite numbers, unit quaternions."""
    try:
        f = open(path, newline="")
    except OSError as e:
        raise BadInput("%s: cannot open: %s" % (path, e.strerror or e))
    with f:
        reader = csv.reader(f)
        try:
            header = next(reader)
        except StopIteration:
            raise BadInput("%s: line 1: empty file (expected the header %s)" % (path, ",".join(COLUMNS)))
        header = [h.strip() for h in header]
        missing = [c for c in COLUMNS if c not in header]
        if missing:
            raise BadInput("%s: line 1: bad header, missing column(s) %s (expected se3_interpolate's %s)"
                           % (path, ",".join(missing), ",".join(COLUMNS)))
        index = [header.index(c) for c in COLUMNS[:8]]
        rows, blank = [], None
        for row in reader:
            line = reader.line_num
            if not row or all(not c.strip() for c in row):
                blank = blank or line
                continue
            if blank is not None:
                raise BadInput("%s: line %d: empty line inside the samples" % (path, blank))
            if len(row) != len(header):
                raise BadInput("%s: line %d: %d fields, the header has %d" % (path, line, len(row), len(header)))
            values = []
            for i in index:
                try:
                    v = float(row[i])
                except ValueError:
                    raise BadInput("%s: line %d: column %s: %r is not a number" % (path, line, header[i], row[i]))
                if not math.isfinite(v):
                    raise BadInput("%s: line %d: column %s: %r is not finite" % (path, line, header[i], row[i]))
                values.append(v)
            n = math.sqrt(sum(c * c for c in values[4:8]))
            if abs(n - 1.0) > 1e-6:
                raise BadInput("%s: line %d: quaternion (qx, qy, qz, qw) has norm %.9g, not 1" % (path, line, n))
            rows.append((line, values))
    if len(rows) < 2:
        raise BadInput("%s: %d sample(s), at least 2 are needed" % (path, len(rows)))
    lines = [r[0] for r in rows]
    a = np.array([r[1] for r in rows])
    return lines, a[:, 0], a[:, 1:4], a[:, 4:8]


def controller_times(path, lines, t, dt):
    """The controller ticks t_0 + k dt the samples are on; BadInput naming the first line off the grid."""
    tol = 1e-6 * dt
    ticks = t[0] + dt * np.arange(len(t))
    for k in range(1, len(t)):
        last = k == len(t) - 1
        if t[k] <= t[k - 1]:
            raise BadInput("%s: line %d: time %.9g does not increase (previous %.9g)"
                           % (path, lines[k], t[k], t[k - 1]))
        off = t[k] - ticks[k]
        if abs(off) > tol and not (last and off < 0):
            raise BadInput("%s: line %d: time %.9g is not on the %g Hz grid (expected %.9g, step %.9g s instead of "
                           "%g s); resample at sample_period %g first" % (path, lines[k], t[k], 1 / dt, ticks[k],
                                                                           t[k] - t[k - 1], dt, dt))
    return ticks


def quat_mul(a, b):
    ax, ay, az, aw = a[:, 0], a[:, 1], a[:, 2], a[:, 3]
    bx, by, bz, bw = b[:, 0], b[:, 1], b[:, 2], b[:, 3]
    return np.stack([aw * bx + ax * bw + ay * bz - az * by,
                     aw * by - ax * bz + ay * bw + az * bx,
                     aw * bz + ax * by - ay * bx + az * bw,
                     aw * bw - ax * bx - ay * by - az * bz], axis=1)


def rotation_steps(q):
    """log(R_k R_{k-1}^T) for consecutive unit quaternions (x, y, z, w): principal rotation vectors."""
    q = q / np.linalg.norm(q, axis=1)[:, None]
    conj = q[:-1] * np.array([-1.0, -1.0, -1.0, 1.0])
    d = quat_mul(q[1:], conj)
    d[d[:, 3] < 0] *= -1.0  # the sign of a quaternion is arbitrary: take the angle in [0, pi]
    n = np.linalg.norm(d[:, :3], axis=1)
    angle = 2.0 * np.arctan2(n, d[:, 3])
    small = n < 1e-12
    scale = np.where(small, 2.0 / np.maximum(d[:, 3], 1e-300), angle / np.where(small, 1.0, n))
    return d[:, :3] * scale[:, None]


def derivatives(steps, dt):
    """Norms of velocity, acceleration and jerk from per-tick displacements (steps[i] from tick i to i+1)."""
    v = steps / dt
    a = np.diff(v, axis=0, prepend=np.zeros((1, 3))) / dt
    j = np.diff(a, axis=0, prepend=np.zeros((1, 3))) / dt
    return v, a, j


def runs(mask):
    """(first, last) index pairs of the runs of True in mask."""
    idx = np.flatnonzero(mask)
    if idx.size == 0:
        return []
    breaks = np.flatnonzero(np.diff(idx) > 1)
    starts = np.concatenate([[idx[0]], idx[breaks + 1]])
    ends = np.concatenate([idx[breaks], [idx[-1]]])
    return list(zip(starts.tolist(), ends.tolist()))


def positive(text):
    try:
        v = float(text)
    except ValueError:
        v = float("nan")
    if not (v > 0 and math.isfinite(v)):
        raise argparse.ArgumentTypeError("expected a positive number, got %s" % text)
    return v


def analyse(t_ticks, p, q, dt):
    """Per-tick norms of the six quantities over the held-padded sequence, and the tick times.

    The sequence is HELD_TICKS copies of the first pose, the samples, HELD_TICKS copies of the last
    pose; a value at index i is the backward difference ending at tick i. Returned from the first
    sample on (the ticks before are at rest by construction)."""
    h = HELD_TICKS
    pp = np.concatenate([np.repeat(p[:1], h, axis=0), p, np.repeat(p[-1:], h, axis=0)])
    qq = np.concatenate([np.repeat(q[:1], h, axis=0), q, np.repeat(q[-1:], h, axis=0)])
    lin = derivatives(np.diff(pp, axis=0), dt)
    ang = derivatives(rotation_steps(qq), dt)
    # difference i (0-based) ends at padded index i + 1; the first sample is padded index h
    values = {}
    for key, (v, a, j) in (("linear", lin), ("angular", ang)):
        values[key + "_velocity"] = np.linalg.norm(v, axis=1)[h - 1:]
        values[key + "_acceleration"] = np.linalg.norm(a, axis=1)[h - 1:]
        values[key + "_jerk"] = np.linalg.norm(j, axis=1)[h - 1:]
    times = np.concatenate([t_ticks, t_ticks[-1] + dt * np.arange(1, h + 1)])
    return values, times


def rest_checks(p, q, dt, tol_v, tol_a):
    """Violations of the rest condition at the start and the end, from the samples alone."""
    out = []
    lin_steps = np.diff(p, axis=0)
    ang_steps = rotation_steps(q)
    for where, sl_v, sl_a in (("start", slice(0, 1), slice(0, 2)), ("end", slice(-1, None), slice(-2, None))):
        for kind, steps, unit in (("linear", lin_steps, "m/s"), ("angular", ang_steps, "rad/s")):
            v = np.linalg.norm(steps[sl_v][0]) / dt
            if v > tol_v:
                out.append((where, "%s velocity" % kind, v, unit, tol_v))
            if len(steps) >= 2:
                s = steps[sl_a]
                a = np.linalg.norm(s[1] - s[0]) / dt ** 2
                if a > tol_a:
                    out.append((where, "%s acceleration" % kind, a, unit + "^2" if unit == "m/s" else "rad/s^2",
                                tol_a))
    return out


def main(argv):
    parser = argparse.ArgumentParser(
        description=__doc__.splitlines()[0],
        epilog="See the module docstring (head of this file) for the differences, the sampling rule and the "
               "libfranka values.")
    parser.add_argument("csv", help="se3_interpolate's CSV, sampled at the controller period")
    parser.add_argument("--rate", type=positive, default=1000.0, metavar="HZ",
                        help="controller rate; the CSV must be sampled at 1/HZ (default 1000)")
    parser.add_argument("--franka", action="store_true",
                        help="libfranka 0.9 nominal Cartesian limits: 2.0 m/s, 13 m/s^2, 6500 m/s^3, "
                             "2.5 rad/s, 25 rad/s^2, 12500 rad/s^3 (--max-* options override single ones)")
    for key, name, unit in QUANTITIES:
        parser.add_argument("--max-" + key.replace("_", "-"), dest=key, type=positive,
                            metavar=unit.upper().replace("/", "_PER_").replace("^", ""),
                            help="limit on |%s| [%s]" % (name, unit))
    parser.add_argument("--rest-velocity-tolerance", type=positive, default=0.01, metavar="V",
                        help="largest |v| [m/s] and |w| [rad/s] over the first/last interval counted as rest "
                             "(default 0.01)")
    parser.add_argument("--rest-acceleration-tolerance", type=positive, default=0.1, metavar="A",
                        help="largest |a| [m/s^2] and |dw/dt| [rad/s^2] over the first/last two intervals "
                             "counted as rest (default 0.1)")
    args = parser.parse_args(argv)
    limits = dict(FRANKA) if args.franka else {}
    for key, _, _ in QUANTITIES:
        if getattr(args, key) is not None:
            limits[key] = getattr(args, key)
    if not limits:
        parser.error("no limits: give --franka or at least one --max-* option")
    dt = 1.0 / args.rate

    try:
        lines, t, p, q = read_csv(args.csv)
        ticks = controller_times(args.csv, lines, t, dt)
    except BadInput as e:
        print("check_controller_limits: error: %s" % e, file=sys.stderr)
        return 2

    values, times = analyse(ticks, p, q, dt)
    violations = []  # (first time, text)
    counts = {}
    for key, name, unit in QUANTITIES:
        if key not in limits:
            continue
        x = values[key]
        for i0, i1 in runs(x > limits[key]):
            peak = i0 + int(np.argmax(x[i0:i1 + 1]))
            n = i1 - i0 + 1
            violations.append((times[i0], "t=%.6f s: %s %.6g %s > limit %.6g %s; until t=%.6f s (%d tick%s), "
                                          "peak %.6g %s at t=%.6f s"
                               % (times[i0], name, x[i0], unit, limits[key], unit, times[i1], n,
                                  "" if n == 1 else "s", x[peak], unit, times[peak])))
            counts[name] = counts.get(name, 0) + 1
    for where, name, value, unit, tol in rest_checks(p, q, dt, args.rest_velocity_tolerance,
                                                     args.rest_acceleration_tolerance):
        when = times[0] if where == "start" else ticks[-1]
        violations.append((when, "t=%.6f s: rest: %s at the %s %.6g %s > rest tolerance %.6g %s"
                           % (when, name, where, value, unit, tol, unit)))
        counts["rest"] = counts.get("rest", 0) + 1
    violations.sort(key=lambda v: v[0])
    for _, text in violations:
        print(text)

    peaks = []
    for key, name, unit in QUANTITIES:
        i = int(np.argmax(values[key]))
        peaks.append("%s %.4g %s at t=%.3f s%s" % (name, values[key][i], unit, times[i],
                                                   " (limit %g)" % limits[key] if key in limits else ""))
    span = "%d samples at %g Hz, t=%.6f..%.6f s" % (len(t), args.rate, t[0], t[-1])
    if violations:
        print("summary: FAIL: %d violation%s (%s); %s; peaks: %s"
              % (len(violations), "" if len(violations) == 1 else "s",
                 ", ".join("%s %d" % kv for kv in counts.items()), span, "; ".join(peaks)))
        return 1
    print("summary: OK: within the limits, at rest at both ends; %s; peaks: %s" % (span, "; ".join(peaks)))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
