#!/usr/bin/python3
"""curve fit against an independent implementation: in the double geodesic the fit's translation is
linear least squares, so with smoothing 0 the control positions se3_interpolate saves
(--save-bspline) must be the coefficients of scipy.interpolate.make_lsq_spline on the same knots
(to 1e-9), for every degree, uneven times (steps from 1 ms to 1 s) and rotations that do
not enter the translation. Run by rostest (test/scripts/fit_scipy.test)."""
import math
import os
import random
import subprocess
import tempfile
import unittest

import numpy as np
import yaml
from scipy.interpolate import make_lsq_spline


def quaternion(rx, ry, rz):
    """Unit quaternion (x, y, z, w) of the rotation vector (rx, ry, rz)."""
    angle = math.sqrt(rx * rx + ry * ry + rz * rz)
    if angle == 0.0:
        return (0.0, 0.0, 0.0, 1.0)
    s = math.sin(angle / 2) / angle
    return (rx * s, ry * s, rz * s, math.cos(angle / 2))


class FitAgainstScipy(unittest.TestCase):
    def setUp(self):
        rng = random.Random(5)
        t = 0.0
        self.times, self.positions, rows = [], [], ["t,x,y,z,qx,qy,qz,qw"]
        for i in range(400):
            p = (math.sin(0.7 * t) + rng.gauss(0, 0.01), 0.3 * t + rng.gauss(0, 0.01), rng.gauss(0, 0.05))
            q = quaternion(0.2 * math.sin(t), rng.gauss(0, 0.3), 0.1 * t)
            if i % 3 == 0:
                q = tuple(-c for c in q)  # the other sign: the same rotation
            self.times.append(t)
            self.positions.append(p)
            rows.append(",".join(repr(v) for v in (t,) + p + q))
            t += 0.001 if i % 9 == 4 else (1.0 if i % 47 == 20 else rng.uniform(0.01, 0.05))
        self.dir = tempfile.mkdtemp()
        self.csv = os.path.join(self.dir, "recording.csv")
        with open(self.csv, "w") as f:
            f.write("\n".join(rows) + "\n")

    def fit(self, degree, control_period):
        request = os.path.join(self.dir, "fit.yaml")
        saved = os.path.join(self.dir, "fitted.yaml")
        with open(request, "w") as f:
            f.write("curve: fit\ndegree: %d\ncontrol_period: %r\nsample_count: 3\n" % (degree, control_period))
        run = subprocess.run(["rosrun", "se3_interpolation", "se3_interpolate", request, "--waypoints", self.csv,
                              "--save-bspline", saved, "-o", os.path.join(self.dir, "out.csv")],
                             capture_output=True, text=True, check=False)
        self.assertEqual(run.returncode, 0, run.stderr)
        with open(saved) as f:
            return yaml.safe_load(f)

    def test_control_positions_are_scipys_least_squares_coefficients(self):
        x = np.array(self.times)
        y = np.array(self.positions)
        for degree, period in ((1, 0.5), (2, 0.6), (3, 0.7), (4, 0.9), (5, 1.1)):
            saved = self.fit(degree, period)
            self.assertEqual(saved["curve"], "bspline")
            self.assertEqual(saved["degree"], degree)
            knots = np.array(saved["knots"], dtype=float)
            intervals = math.ceil((x[-1] - x[0]) / period - 1e-9)
            self.assertEqual(len(knots), intervals + 2 * degree + 1)
            ours = np.array([w["position"] for w in saved["waypoints"]], dtype=float)
            spline = make_lsq_spline(x, y, knots, k=degree)
            self.assertEqual(spline.c.shape, ours.shape)
            error = np.max(np.abs(spline.c - ours))
            self.assertLess(error, 1e-9, "degree %d: %g" % (degree, error))

    def test_the_check_can_fail(self):
        # Another knot vector gives other coefficients: the comparison above is not vacuous.
        x = np.array(self.times)
        y = np.array(self.positions)
        saved = self.fit(3, 0.7)
        knots = np.array(saved["knots"], dtype=float)
        shifted = knots.copy()
        shifted[5] += 0.05
        other = make_lsq_spline(x, y, shifted, k=3)
        ours = np.array([w["position"] for w in saved["waypoints"]], dtype=float)
        self.assertGreater(np.max(np.abs(other.c - ours)), 1e-4)


if __name__ == "__main__":
    import rostest

    rostest.rosrun("se3_interpolation", "fit_scipy", FitAgainstScipy)
