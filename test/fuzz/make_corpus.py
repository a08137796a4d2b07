#!/usr/bin/env python3
"""Writes the seed corpus of the request targets fuzz_generate, fuzz_validate and fuzz_curves
(test/fuzz/corpus/): one small input per curve in the byte format of fuzz_common.h's decode(),
plus a text seed and an empty one; and the seed corpus of fuzz_c2 (test/fuzz/corpus_c2/): C^2
solves in each space in the format of fuzz_c2.cpp.
Usage: python3 test/fuzz/make_corpus.py [OUT_DIR [C2_OUT_DIR]]"""
import math
import os
import sys

CURVES = ["piecewise_geodesic", "bezier", "bspline", "interpolating", "hermite", "blended"]
GEOMETRIES = ["double_geodesic", "screw"]
END_CONDITIONS = ["natural", "clamped", "start"]
PARAMETERIZATIONS = ["chord", "uniform", "centripetal"]


class Encoder:
    def __init__(self):
        self.out = bytearray()

    def byte(self, b):
        assert 0 <= b < 256
        self.out.append(b)

    def small(self, x):
        """A value of ByteReader::small(): (b - 128) / 16."""
        b = round(x * 16) + 128
        assert abs((b - 128) / 16 - x) < 1e-12, x
        self.byte(b)

    def number(self, x):
        self.byte(0)  # tag 0: a small number follows
        self.small(x)

    def optional(self, x=None):
        if x is None:
            self.byte(1)  # 0, the default
        else:
            self.byte(0)
            self.number(x)

    def name(self, valid, value):
        if value == "":
            self.byte(0)
            return
        k = valid.index(value)
        self.byte(next(b for b in range(1, 200) if b % 4 != 0 and b % len(valid) == k))

    def sequence(self, start, steps):
        """Increasing numbers: start, then each step in multiples of 1/8 (the last is unused)."""
        self.byte(1)
        self.small(start)
        for s in steps:
            self.byte(round(s * 8))

    def twist(self, linear=None, angular=None):
        if linear is None:
            self.byte(0)
            return
        self.byte(1)
        for x in list(linear) + list(angular):
            self.number(x)


def rotation(axis, angle):
    """A quaternion (x, y, z, w) as the four small values of quaternion mode 0 (normalised
    by the decoder, so only the direction matters; multiples of 1/16 within [-8, 8))."""
    n = math.sqrt(sum(a * a for a in axis))
    s = math.sin(angle / 2)
    q = [a / n * s for a in axis] + [math.cos(angle / 2)]
    return [round(c * 64) / 16 for c in q]


def request(waypoints, curve="", geometry="", end_condition="", parameterization="", times=None,
            degree=0, knots=None, continuity=0, start_velocity=None, end_velocity=None,
            start_acceleration=None, velocities=None, rotation_scale=None, duration=None,
            bounds=(None, None, None, None), sample_times=None, sample_period=None, sample_count=20):
    e = Encoder()
    e.byte(len(waypoints))
    for position, quaternion in waypoints:
        e.byte(1)  # an explicit position
        for x in position:
            e.number(x)
        e.byte(0)  # quaternion mode 0
        for c in quaternion:
            e.small(c)
    e.name(CURVES, curve)
    e.name(GEOMETRIES, geometry)
    e.name(END_CONDITIONS, end_condition)
    e.name(PARAMETERIZATIONS, parameterization)
    if times is None:
        e.byte(0)
    else:
        e.byte(1)
        e.sequence(times[0], [b - a for a, b in zip(times, times[1:])] + [1])
    e.byte(degree)
    if knots is None:
        e.byte(0)
    else:
        e.byte(1)
        e.sequence(knots[0], [b - a for a, b in zip(knots, knots[1:])] + [1])
    e.byte(continuity + 1)
    for t in (start_velocity, end_velocity, start_acceleration):
        e.twist(*(t or (None, None)))
    if velocities is None:
        e.byte(0)
    else:
        e.byte(1)
        for v in velocities:
            e.twist(*v)
    for x in (rotation_scale, duration) + tuple(bounds):
        e.optional(x)
    if sample_times is None:
        e.byte(0)
    else:
        e.byte(1)
        e.byte(len(sample_times))
        e.sequence(sample_times[0], [b - a for a, b in zip(sample_times, sample_times[1:])] + [1])
    e.optional(sample_period)
    e.byte(sample_count)
    return bytes(e.out)


def c2_solve(space, points, start, steps, clamped=False, velocities=((0,) * 6, (0,) * 6), evaluations=(0.25, 0.75),
             dim=3, project=True):
    """An input of fuzz_c2.cpp: space 0 double geodesic, 1 screw, 2 the sphere S^(dim - 1);
    SE(3) points are (position, quaternion as rotation() gives it), sphere points vectors (unit
    after the decoder's normalisation) or "antipodal" for the previous point's negation; the
    times start at `start` and increase by `steps`, multiples of 1/8, each optionally times
    10^k for k in [-6, 4] (a (step, k) pair)."""
    e = Encoder()
    e.byte(space)
    e.byte(len(points) - 2)
    if space == 2:
        e.byte(dim - 3)
    for i, x in enumerate(points):
        if space == 2:
            if x == "antipodal":
                e.byte(0)
            else:
                e.byte(2)  # a new point
                for c in x:
                    e.small(c)
            continue
        position, quaternion = x
        if i > 0:
            e.byte(1)  # a new position, not the previous one
        for c in position:
            e.small(c)
            e.byte(1)  # not scaled
        e.byte(0)  # quaternion mode 0
        for c in quaternion:
            e.small(c)
    e.small(start)
    for step in steps:
        step, scale = step if isinstance(step, tuple) else (step, None)
        e.byte(round(step * 8))
        if scale is None:
            e.byte(1)
        else:
            e.byte(0)
            e.byte(scale + 6)  # ByteReader::range(-6, 4)
    e.byte(1 if clamped else 0)
    for v in velocities:
        for c in v[:dim if space == 2 else 6]:
            e.small(c)
        if space == 2:
            e.byte(1 if project else 0)
    e.byte(1)  # the fuzz target's Newton budget (kFuzzIterations)
    e.byte(len(evaluations))
    for u in evaluations:
        e.byte(round(u * 255))
    return bytes(e.out)


def c2_seeds():
    z = (0, 0, 1)
    x = (1, 0, 0)
    poses = [((0, 0, 0), rotation(z, 0.0)), ((1, 0.5, 0), rotation(z, 1.0)), ((2, 1, 0.5), rotation(x, 1.5)),
             ((3, 0, 1), rotation((1, 1, 0), 2.5)), ((4, -1, 1), rotation(z, -1.0)), ((5, 0, 0), rotation(x, 3.0))]
    moving = (0.5, 0, 0, 0, 0, 0.25)
    circle = [(1, 0, 0), (0, 1, 0), (-1, 0, 0.5), (0, -1, 1)]
    return {
        "double_geodesic_natural": c2_solve(0, poses[:3], 0, [1, 1.5]),
        "double_geodesic_two": c2_solve(0, poses[:2], 0, [1]),
        "double_geodesic_six": c2_solve(0, poses, 0, [0.5, 0.5, 1, 0.5, 1.5]),
        "screw_clamped": c2_solve(1, poses[:4], 0, [1, 1, 1], clamped=True, velocities=(moving, moving)),
        "screw_natural": c2_solve(1, poses[1:5], -1, [1, 0.25, 1.25]),
        "uneven_times": c2_solve(0, poses[:4], 0, [1, (4, -3), (1, 3)]),
        "sphere_natural": c2_solve(2, circle, 0, [1, 1, 1]),
        "sphere_s3_clamped": c2_solve(2, [(1, 0, 0, 0), (0, 1, 0, 1), (0, 0, 1, 1)], 0, [1, 2], clamped=True,
                                      velocities=((0, 0.5, 0, 0), (0.25, 0, 0, 0)), dim=4),
        "sphere_antipodal": c2_solve(2, [(1, 0, 0), "antipodal", (0, 1, 0)], 0, [1, 1]),
    }


def main():
    here = os.path.dirname(os.path.abspath(__file__))
    out = sys.argv[1] if len(sys.argv) > 1 else os.path.join(here, "corpus")
    c2_out = sys.argv[2] if len(sys.argv) > 2 else os.path.join(here, "corpus_c2")
    os.makedirs(c2_out, exist_ok=True)
    for name, data in c2_seeds().items():
        with open(os.path.join(c2_out, name), "wb") as f:
            f.write(data)
    os.makedirs(out, exist_ok=True)
    z = (0, 0, 1)
    x = (1, 0, 0)
    poses = [((0, 0, 0), rotation(z, 0.0)), ((1, 0.5, 0), rotation(z, 1.0)), ((2, 1, 0.5), rotation(x, 1.5)),
             ((3, 0, 1), rotation((1, 1, 0), 2.5)), ((4, -1, 1), rotation(z, -1.0))]
    moving = ((0.5, 0, 0), (0, 0, 0.25))
    seeds = {
        "piecewise_geodesic": request(poses[:3], curve="piecewise_geodesic", parameterization="centripetal"),
        "bezier_screw": request(poses[:4], curve="bezier", geometry="screw", times=[0, 1, 2.5, 3]),
        "bspline_knots": request(poses, curve="bspline", degree=3, knots=[0, 0, 0, 0, 1, 2, 2, 2, 2]),
        "interpolating_clamped": request(poses[:4], curve="interpolating", end_condition="clamped",
                                         start_velocity=moving, end_velocity=moving, duration=4),
        "interpolating_start": request(poses[:2], curve="interpolating", end_condition="start",
                                       start_velocity=moving, start_acceleration=moving),
        "hermite_velocities": request(poses[:3], curve="hermite", velocities=[moving] * 3,
                                      sample_times=[0, 0.5, 1, 2]),
        "blended_bounds": request(poses, curve="blended", continuity=3, bounds=(0.5, 1, 2, None),
                                  sample_period=0.25),
        "blended_twelve": request([((0.5 * i, (i % 3) * 0.5, 0), rotation((1, i % 2, 1), 0.3 * i)) for i in range(12)],
                                  curve="blended", geometry="screw", parameterization="uniform", continuity=4),
        "text": b"curve: bspline\ndegree: 2\nwaypoints: [{position: [0, 0, 0]}]\n",
        "empty": b"",
    }
    for name, data in seeds.items():
        with open(os.path.join(out, name), "wb") as f:
            f.write(data)


if __name__ == "__main__":
    main()
