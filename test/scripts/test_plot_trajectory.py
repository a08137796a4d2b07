#!/usr/bin/python3
"""scripts/plot_trajectory.py: the unwrapped rotation vector against closed forms (rotations about
one axis, through and beyond pi, with quaternion sign flips), the jerk from differences of the
accelerations, the CLI figures it reads, and a PNG from standard input. Run by rostest
(test/scripts/plot_trajectory.test)."""
import importlib.util
import io
import math
import os
import sys
import tempfile
import unittest

HERE = os.path.dirname(os.path.abspath(__file__))
spec = importlib.util.spec_from_file_location("plot_trajectory",
                                              os.path.join(HERE, "..", "..", "scripts", "plot_trajectory.py"))
plot = importlib.util.module_from_spec(spec)
spec.loader.exec_module(plot)


def about(axis, angle):
    """Unit quaternion (x, y, z, w) of a rotation by angle about the unit axis."""
    s = math.sin(angle / 2)
    return (axis[0] * s, axis[1] * s, axis[2] * s, math.cos(angle / 2))


class PlotTrajectory(unittest.TestCase):
    def check(self, axis, angles, flip_every=0):
        qs = [about(axis, a) for a in angles]
        if flip_every:
            qs = [tuple(-c for c in q) if (i // flip_every) % 2 else q for i, q in enumerate(qs)]
        rv = plot.unwrap([plot.rotation_vector(q) for q in qs])
        for a, r in zip(angles, rv):
            for c, n in zip(r, axis):
                self.assertAlmostEqual(c, a * n, delta=1e-12, msg="angle %r" % a)

    def test_about_z_past_pi_has_no_jump(self):
        # Principal vectors jump from +pi to -pi at pi; the unwrapped one is the angle itself.
        self.check((0.0, 0.0, 1.0), [1.5 * math.pi * i / 100 for i in range(101)])

    def test_oblique_axis_to_three_and_a_half_turns_with_sign_flips(self):
        n = (1 / math.sqrt(3), -1 / math.sqrt(3), 1 / math.sqrt(3))
        self.check(n, [7.0 * math.pi * i / 350 for i in range(351)], flip_every=7)

    def test_through_pi_minus_and_plus_epsilon(self):
        self.check((0.0, 1.0, 0.0), [0.0, 1.0, math.pi - 1e-9, math.pi + 1e-9, 4.0])

    def test_backwards_below_zero(self):
        self.check((1.0, 0.0, 0.0), [-4.0 * i / 50 for i in range(51)])

    def test_figures_and_waypoint_times(self):
        with tempfile.NamedTemporaryFile("w", suffix=".txt", delete=False) as f:
            f.write("duration: 2\nenergy: 1e-30\nwaypoint_times: 0, 0.5, 1.5, 2\n")
        figures = plot.read_figures(f.name)
        os.unlink(f.name)
        self.assertEqual(figures["waypoint_times"], [0.0, 0.5, 1.5, 2.0])
        self.assertEqual(figures["duration"], 2.0)
        self.assertEqual(figures["energy"], 1e-30)

    def test_constant_speed_window(self):
        self.assertEqual(plot.constant_speed_window({"constant_speed_start": 0.9375, "constant_speed_end": 4.0}),
                         (0.9375, 4.0))
        self.assertIsNone(plot.constant_speed_window({"duration": 2.0}))
        self.assertIsNone(plot.constant_speed_window({"constant_speed_start": 1.0, "constant_speed_end": 1.0}))

    def test_jerk_from_accelerations(self):
        # a(t) = (t^2, -2 t, 0.5) has jerk (2 t, -2, 0): the difference quotient over [t0, t1] is the
        # jerk at the midpoint exactly (a is quadratic); uneven intervals, one repeated time skipped.
        t = [0.0, 0.1, 0.3, 0.3, 0.6, 1.0]
        mid, mags = plot.jerk(t, [x * x for x in t], [-2 * x for x in t], [0.5] * len(t))
        expected_mid = [0.05, 0.2, 0.45, 0.8]
        self.assertEqual(len(mid), len(expected_mid))
        for m, e, j in zip(mid, expected_mid, mags):
            self.assertAlmostEqual(m, e, delta=1e-15)
            self.assertAlmostEqual(j, math.hypot(2 * e, 2.0), delta=1e-12)
        self.assertEqual(plot.jerk([0.0], [1.0], [2.0], [3.0]), ([], []))

    def test_png_from_standard_input_and_errors(self):
        header = ",".join(plot.COLUMNS)
        rows = ["%g,%g,0,0,0,0,%r,%r" % (t, t, math.sin(t), math.cos(t)) + ",1,0,0,0,0,2" + ",0" * 6
                for t in [i * 0.1 for i in range(40)]]
        out = os.path.join(tempfile.mkdtemp(), "plot.png")
        stdin = sys.stdin
        try:
            sys.stdin = io.StringIO(header + "\n" + "\n".join(rows) + "\n")
            self.assertEqual(plot.main(["-", out, "--max-linear-velocity", "1.5", "--max-linear-jerk", "5",
                                        "--max-angular-jerk", "10"]), 0)
            sys.stdin = io.StringIO(header + "\n" + rows[0] + "\n")  # one sample: no jerk to draw
            self.assertEqual(plot.main(["-", out + ".one.png"]), 0)
            with self.assertRaises(SystemExit) as bad:
                plot.main(["-", out + ".bad.png", "--max-angular-jerk", "-1"])
            self.assertEqual(bad.exception.code, 2)
            sys.stdin = io.StringIO("t,x\n0,1\n")
            self.assertEqual(plot.main(["-", out + ".bad.png"]), 2)
        finally:
            sys.stdin = stdin
        with open(out, "rb") as f:
            self.assertEqual(f.read(8), b"\x89PNG\r\n\x1a\n")
        self.assertFalse(os.path.exists(out + ".bad.png"))


if __name__ == "__main__":
    import rostest
    rostest.rosrun("se3_interpolation", "plot_trajectory", PlotTrajectory)
