#!/usr/bin/python3
"""scripts/check_controller_limits.py on synthetic CSVs with closed-form motions sampled at 1 kHz:
a rest-to-rest quintic within the Franka limits, trapezoid profiles (acceleration steps) in
translation and in rotation whose jerk at the switches breaks them, rest, rate and input errors.

Plain unittest, no ROS: /usr/bin/python3 test/scripts/test_check_controller_limits.py

Jerk of an acceleration step as a pose-only controller sees it: a step A at time s between samples
gives backward third differences of the sampled positions A/dt times the quadratic B-spline at the
step's phase: 0.5 A/dt at two ticks when s is on a tick, 0.125, 0.75, 0.125 A/dt at three ticks
when s is half-way between ticks. So a 10 m/s^2 step switched on half-way between ticks peaks at
7500 m/s^3 (> 6500) at the second tick after it, and one on a tick at 5000 m/s^3 (< 6500) twice.
"""
import math
import os
import re
import subprocess
import sys
import tempfile
import unittest

HERE = os.path.dirname(os.path.abspath(__file__))
SCRIPT = os.path.join(HERE, "..", "..", "scripts", "check_controller_limits.py")
HEADER = "t,x,y,z,qx,qy,qz,qw,vx,vy,vz,wx,wy,wz,ax,ay,az,alx,aly,alz"
DT = 0.001
U = (1 / 3, 2 / 3, 2 / 3)          # unit direction of the straight lines
N = (2 / 3, -1 / 3, 2 / 3)         # unit rotation axis
P0 = (0.1, 0.2, 0.5)


def quintic(T, D):
    """s(t), s'(t), s''(t) of the rest-to-rest quintic from 0 to D in time T."""
    def f(t):
        u = min(max(t / T, 0.0), 1.0)
        return (D * (10 * u ** 3 - 15 * u ** 4 + 6 * u ** 5),
                D * (30 * u ** 2 - 60 * u ** 3 + 30 * u ** 4) / T,
                D * (60 * u - 180 * u ** 2 + 120 * u ** 3) / T ** 2)
    return f


def trapezoid(A, switches):
    """s, s', s'' of the profile s'' = A on [s0, s1), 0 on [s1, s2), -A on [s2, s3), 0 elsewhere
    (rest before s0 and after s3 when s1 - s0 = s3 - s2)."""
    s0, s1, s2, s3 = switches

    def f(t):
        if t <= s0:
            return 0.0, 0.0, 0.0
        vmax = A * (s1 - s0)
        d1 = 0.5 * A * (s1 - s0) ** 2
        if t <= s1:
            h = t - s0
            return 0.5 * A * h * h, A * h, A
        if t <= s2:
            return d1 + vmax * (t - s1), vmax, 0.0
        d2 = d1 + vmax * (s2 - s1)
        if t <= s3:
            h = t - s2
            return d2 + vmax * h - 0.5 * A * h * h, vmax - A * h, -A
        return d2 + vmax * (s3 - s2) - 0.5 * A * (s3 - s2) ** 2, 0.0, 0.0
    return f


def row(t, p, q, v=(0, 0, 0), w=(0, 0, 0), a=(0, 0, 0), al=(0, 0, 0)):
    return ",".join(repr(float(c)) for c in (t,) + tuple(p) + tuple(q) + tuple(v) + tuple(w) + tuple(a) + tuple(al))


def line_motion(profile, times):
    """Rows of a straight-line translation P0 + s(t) U, identity orientation."""
    out = []
    for t in times:
        s, sd, sdd = profile(t)
        out.append(row(t, [p + s * u for p, u in zip(P0, U)], (0, 0, 0, 1),
                       v=[sd * u for u in U], a=[sdd * u for u in U]))
    return out


def rotation_motion(profile, times, flip=True):
    """Rows of a rotation by s(t) about N at the fixed position P0; every other quaternion negated."""
    out = []
    for k, t in enumerate(times):
        s, sd, sdd = profile(t)
        h = math.sin(s / 2)
        q = [N[0] * h, N[1] * h, N[2] * h, math.cos(s / 2)]
        if flip and k % 2:
            q = [-c for c in q]
        out.append(row(t, P0, q, w=[sd * n for n in N], al=[sdd * n for n in N]))
    return out


def grid(duration, dt=DT):
    n = int(round(duration / dt))
    return [k * dt for k in range(n + 1)]


class CheckControllerLimits(unittest.TestCase):
    def setUp(self):
        self.dir = tempfile.mkdtemp(prefix="check_limits_")

    def write(self, name, rows, header=HEADER):
        path = os.path.join(self.dir, name)
        with open(path, "w") as f:
            f.write(header + "\n" + "\n".join(rows) + "\n")
        return path

    def run_script(self, *args):
        r = subprocess.run([sys.executable, SCRIPT] + [str(a) for a in args], stdout=subprocess.PIPE,
                           stderr=subprocess.PIPE, universal_newlines=True, timeout=120)
        return r.returncode, r.stdout, r.stderr

    def violations(self, out):
        """(time, quantity, first value, last time, ticks, peak) of each violation line."""
        found = []
        for line in out.splitlines():
            m = re.match(r"t=([\d.]+) s: ([a-z ]+?) ([\d.e+-]+) \S+ > limit [\d.e+-]+ \S+; until t=([\d.]+) s "
                         r"\((\d+) ticks?\), peak ([\d.e+-]+) ", line)
            if m:
                found.append((float(m.group(1)), m.group(2), float(m.group(3)), float(m.group(4)),
                              int(m.group(5)), float(m.group(6))))
        return found

    def test_quintic_within_franka_limits(self):
        # 0.3 m in 1 s: peaks 0.5625 m/s, 1.73 m/s^2, 18 m/s^3; with a 0.2 s hold at the end.
        path = self.write("quintic.csv", line_motion(quintic(1.0, 0.3), grid(1.2)))
        code, out, err = self.run_script(path, "--franka")
        self.assertEqual(code, 0, out + err)
        self.assertEqual(self.violations(out), [])
        self.assertTrue(out.splitlines()[-1].startswith("summary: OK"), out)
        m = re.search(r"linear velocity ([\d.]+) m/s", out)
        self.assertAlmostEqual(float(m.group(1)), 0.5625, delta=1e-3)
        m = re.search(r"linear jerk ([\d.]+) m/s\^3", out)
        self.assertAlmostEqual(float(m.group(1)), 18.0, delta=0.2)

    def test_acceleration_steps_break_linear_jerk(self):
        # 10 m/s^2 switched on, off, on (negative) and off half-way between ticks: 7500 m/s^3 at
        # the second tick after each switch, nothing else (1 m/s, 10 m/s^2 are within the limits).
        switches = (0.1005, 0.2005, 0.4005, 0.5005)
        path = self.write("trapezoid.csv", line_motion(trapezoid(10.0, switches), grid(0.6)))
        code, out, err = self.run_script(path, "--franka")
        self.assertEqual(code, 1, out + err)
        found = self.violations(out)
        self.assertEqual([(round(v[0], 6), v[1], round(v[3], 6), v[4]) for v in found],
                         [(round(s + 0.0015, 6), "linear jerk", round(s + 0.0015, 6), 1) for s in switches], out)
        for v in found:
            self.assertAlmostEqual(v[2], 7500.0, delta=1.0)
            self.assertAlmostEqual(v[5], 7500.0, delta=1.0)
        self.assertIn("summary: FAIL: 4 violations (linear jerk 4)", out)

    def test_acceleration_step_on_a_tick_is_two_ticks_of_half(self):
        # The same steps on ticks: 5000 m/s^3 at the two ticks after each switch: within 6500, and
        # one grouped line of two ticks per switch against a 4000 m/s^3 limit.
        switches = (0.1, 0.2, 0.4, 0.5)
        path = self.write("trapezoid_on_ticks.csv", line_motion(trapezoid(10.0, switches), grid(0.6)))
        code, out, err = self.run_script(path, "--franka")
        self.assertEqual(code, 0, out + err)
        code, out, err = self.run_script(path, "--franka", "--max-linear-jerk", 4000)
        self.assertEqual(code, 1, out + err)
        found = self.violations(out)
        self.assertEqual([(round(v[0], 6), v[1], round(v[3], 6), v[4]) for v in found],
                         [(round(s + 0.001, 6), "linear jerk", round(s + 0.002, 6), 2) for s in switches], out)
        for v in found:
            self.assertAlmostEqual(v[5], 5000.0, delta=1.0)

    def test_rotation_steps_break_angular_jerk(self):
        # 20 rad/s^2 about a fixed oblique axis, switched half-way between ticks: 15000 rad/s^3
        # (> 12500) at the second tick after each switch; 2 rad/s and 20 rad/s^2 are within the
        # limits, nothing linear; quaternion signs alternate.
        switches = (0.1005, 0.2005, 0.4005, 0.5005)
        path = self.write("rotation.csv", rotation_motion(trapezoid(20.0, switches), grid(0.6)))
        code, out, err = self.run_script(path, "--franka")
        self.assertEqual(code, 1, out + err)
        found = self.violations(out)
        self.assertEqual([(round(v[0], 6), v[1], v[4]) for v in found],
                         [(round(s + 0.0015, 6), "angular jerk", 1) for s in switches], out)
        for v in found:
            self.assertAlmostEqual(v[5], 15000.0, delta=2.0)
        m = re.search(r"angular velocity ([\d.]+) rad/s", out)
        self.assertAlmostEqual(float(m.group(1)), 2.0, delta=1e-6)
        m = re.search(r"linear velocity ([\d.e+-]+) m/s", out)
        self.assertEqual(float(m.group(1)), 0.0)

    def test_not_at_rest(self):
        # The quintic cut at half-time ends at its top speed: a rest violation at the end, and the
        # stop to the held pose is a jump the controller sees (0.5625 m/s in one tick).
        path = self.write("cut.csv", line_motion(quintic(1.0, 0.3), grid(0.5)))
        code, out, err = self.run_script(path, "--franka")
        self.assertEqual(code, 1, out + err)
        self.assertRegex(out, r"t=0\.500000 s: rest: linear velocity at the end 0\.56\d* m/s > rest tolerance 0\.01")
        self.assertIn("linear acceleration", out)

    def test_held_pose_before_and_after(self):
        # Starting with 10 m/s^2 at t = 0 and ending at t = 0.4 still decelerating at 10 m/s^2
        # (velocity 0 there): the controller holds the first pose before and the last after, so
        # it sees a 10 m/s^2 step on a tick at each end: 5000 m/s^3 at 0.001, 0.002 and at the
        # held ticks 0.401, 0.402 (besides the two inner switches at 0.1 and 0.3); and the rest
        # check reports the accelerations at both ends.
        path = self.write("ends.csv", line_motion(trapezoid(10.0, (0.0, 0.1, 0.3, 0.4)), grid(0.4)))
        code, out, err = self.run_script(path, "--franka", "--max-linear-jerk", 4000)
        self.assertEqual(code, 1, out + err)
        found = self.violations(out)
        self.assertEqual([(round(v[0], 6), v[1], round(v[3], 6), v[4]) for v in found],
                         [(round(s + 0.001, 6), "linear jerk", round(s + 0.002, 6), 2) for s in (0.0, 0.1, 0.3, 0.4)],
                         out)
        self.assertRegex(out, r"t=0\.000000 s: rest: linear acceleration at the start 10 m/s\^2")
        self.assertRegex(out, r"t=0\.400000 s: rest: linear acceleration at the end 10 m/s\^2")
        code, out, err = self.run_script(path, "--franka", "--rest-acceleration-tolerance", 10.5)
        self.assertEqual(code, 0, out + err)

    def test_last_interval_may_be_shorter(self):
        times = grid(1.2)[:-1] + [1.1994]
        path = self.write("short_end.csv", line_motion(quintic(1.0, 0.3), times))
        code, out, err = self.run_script(path, "--franka")
        self.assertEqual(code, 0, out + err)

    def test_rate_option(self):
        path = self.write("500hz.csv", line_motion(quintic(1.0, 0.3), grid(1.2, 0.002)))
        code, out, err = self.run_script(path, "--franka", "--rate", 500)
        self.assertEqual(code, 0, out + err)
        code, out, err = self.run_script(path, "--franka")
        self.assertEqual(code, 2, out + err)
        self.assertIn("line 3: time 0.002 is not on the 1000 Hz grid", err)

    def test_non_uniform_time_column(self):
        rows = line_motion(quintic(1.0, 0.3), grid(1.2))
        rows[500] = "0.5004" + rows[500][rows[500].index(","):]  # sample 500 is on line 502
        code, out, err = self.run_script(self.write("jitter.csv", rows), "--franka")
        self.assertEqual(code, 2, out + err)
        self.assertIn("line 502: time 0.5004 is not on the 1000 Hz grid", err)
        self.assertEqual(out, "")
        rows = line_motion(quintic(1.0, 0.3), grid(1.2))
        rows[10] = rows[9]
        code, out, err = self.run_script(self.write("repeat.csv", rows), "--franka")
        self.assertEqual(code, 2, out + err)
        self.assertIn("line 12: time 0.009 does not increase", err)

    def test_malformed_lines(self):
        good = line_motion(quintic(1.0, 0.3), grid(0.1))
        def replaced(r, column, text):
            fields = r.split(",")
            fields[column] = text
            return ",".join(fields)
        # (sample index, new line, message); sample k is on line k + 2
        cases = [(35, replaced(good[35], 1, "abc"), "line 37: column x: 'abc' is not a number"),
                 (40, ",".join(good[40].split(",")[:5]), "line 42: 5 fields, the header has 20"),
                 (50, replaced(good[50], 3, "nan"), "line 52: column z: 'nan' is not finite"),
                 (60, replaced(good[60], 7, "0.5"), "line 62: quaternion (qx, qy, qz, qw) has norm 0.5")]
        for index, line, message in cases:
            rows = list(good)
            rows[index] = line
            code, out, err = self.run_script(self.write("bad%d.csv" % index, rows), "--franka")
            self.assertEqual(code, 2, out + err)
            self.assertIn(message, err)
        rows = list(good)
        rows.insert(20, "")
        code, out, err = self.run_script(self.write("blank.csv", rows), "--franka")
        self.assertEqual(code, 2, out + err)
        self.assertIn("line 22: empty line inside the samples", err)

    def test_bad_header_missing_file_and_no_limits(self):
        path = self.write("header.csv", line_motion(quintic(1.0, 0.3), grid(0.1)), header=HEADER.replace("qw", "w"))
        code, out, err = self.run_script(path, "--franka")
        self.assertEqual(code, 2, out + err)
        self.assertIn("line 1: bad header, missing column(s) qw", err)
        code, out, err = self.run_script(os.path.join(self.dir, "absent.csv"), "--franka")
        self.assertEqual(code, 2, out + err)
        self.assertIn("absent.csv: cannot open", err)
        code, out, err = self.run_script(path)
        self.assertEqual(code, 2, out + err)
        self.assertIn("no limits", err)


if __name__ == "__main__":
    import rostest
    rostest.rosrun("se3_interpolation", "check_controller_limits", CheckControllerLimits)
