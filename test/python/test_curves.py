"""Curves as objects: one builder per registered family, evaluate() at arrays of times, equal to
generate()'s samples of the same curve, and the timings applied to a curve."""

import numpy as np
import pytest

import se3_interpolation as s
from conftest import WAYPOINTS

FAMILIES = [f for f in s.CURVE_FAMILIES if f != "fit"]


def test_every_family_has_a_builder():
    assert {"interpolating", "bspline", "bezier", "hermite", "blended", "piecewise_geodesic", "fit"} <= set(
        s.CURVE_FAMILIES
    )
    for family in s.CURVE_FAMILIES:
        assert callable(getattr(s, family))


@pytest.mark.parametrize("geometry", ["double_geodesic", "screw"])
@pytest.mark.parametrize("family", FAMILIES)
def test_evaluate_equals_generates_samples(family, geometry):
    curve = getattr(s, family)(WAYPOINTS, geometry=geometry)
    assert curve.family == family and curve.start_time == 0.0
    motion = s.generate(waypoints=WAYPOINTS, curve=family, geometry=geometry, sample_count=41)
    pose, velocity, acceleration = curve.evaluate(motion.t)
    assert np.array_equal(pose, motion.pose)
    assert np.array_equal(velocity, motion.velocity)
    assert np.array_equal(acceleration, motion.acceleration)
    assert np.array_equal(curve.waypoint_times, motion.waypoint_times)


def test_velocity_is_the_derivative_of_the_pose():
    curve = s.interpolating(WAYPOINTS, geometry="screw", times=[0, 1, 2, 3])
    t = np.linspace(0.1, 2.9, 15)
    h = 1e-6
    ahead, behind = curve.evaluate(t + h).pose, curve.evaluate(t - h).pose
    velocity = curve.evaluate(t).velocity
    np.testing.assert_allclose((ahead[:, :3] - behind[:, :3]) / (2 * h), velocity[:, :3], atol=1e-6)


def test_the_control_polygon_and_breakpoints():
    curve = s.bspline(WAYPOINTS, degree=2)
    assert curve.control_poses.shape == (4, 7)
    np.testing.assert_allclose(curve.control_poses, curve.waypoints)
    assert curve.breakpoints[0] == curve.start_time and curve.breakpoints[-1] == curve.end_time
    assert "bspline" in repr(curve)


def test_times_outside_the_curve_and_timing_fields_are_refused():
    curve = s.hermite(WAYPOINTS)
    with pytest.raises(s.InvalidInputError, match=r"^t\[1\]: .* is outside the curve"):
        curve.evaluate([0.0, curve.end_time + 1.0])
    with pytest.raises(s.InvalidInputError, match=r"^t\[0\]: nan is outside"):
        curve.evaluate([float("nan")])
    with pytest.raises(s.InvalidInputError, match="^max_linear_velocity: not a field of a curve"):
        s.interpolating(WAYPOINTS, max_linear_velocity=1.0)
    with pytest.raises(TypeError):
        s.make_curve("bezier", WAYPOINTS, curve="bspline")


@pytest.mark.parametrize(
    "timing",
    [
        dict(timing="time_optimal", max_linear_velocity=0.5, max_angular_velocity=1.0,
             max_linear_acceleration=1.0, max_angular_acceleration=2.0),
        dict(timing="time_optimal", max_linear_velocity=0.5, max_angular_velocity=1.0,
             max_linear_acceleration=1.0, max_angular_acceleration=2.0, max_linear_jerk=5.0, max_angular_jerk=10.0),
        dict(timing="constant_speed", speed=0.2, max_linear_acceleration=1.0, max_angular_acceleration=2.0),
    ],
    ids=["time_optimal", "jerk_limited", "constant_speed"],
)
def test_a_curve_is_timed_by_the_timings(timing):
    curve = s.interpolating(WAYPOINTS, geometry="screw")
    motion = curve.timed(sample_count=2001, **timing)
    same = s.generate(dict(curve.fields, sample_count=2001, **timing))
    assert np.array_equal(motion.pose, same.pose)
    for bound, figure in [("max_linear_velocity", "max_linear_speed"),
                          ("max_linear_acceleration", "peak_linear_acceleration"),
                          ("max_linear_jerk", "peak_linear_jerk")]:
        if bound in timing:
            assert getattr(motion, figure) <= timing[bound] * (1 + 1e-6)
    assert motion.duration > curve.end_time - curve.start_time or timing["timing"] == "constant_speed"
    if timing["timing"] == "constant_speed":
        assert motion.constant_speed_end > motion.constant_speed_start > 0.0
