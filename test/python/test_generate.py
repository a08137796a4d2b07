"""generate(): the shapes of its answer, the spellings of a request, the defaults, q versus -q,
and the GIL released while the planner works."""

import threading

import numpy as np
import pytest

import se3_interpolation as s
from conftest import WAYPOINTS

FAMILIES = [f for f in s.CURVE_FAMILIES if f != "fit"]


def test_the_answer_has_the_documented_shapes():
    r = s.generate(waypoints=WAYPOINTS, sample_count=37)
    assert r.t.shape == (37,) and r.pose.shape == (37, 7)
    assert r.velocity.shape == (37, 6) and r.acceleration.shape == (37, 6)
    assert r.waypoint_times.shape == (4,) and r.waypoints.shape == (4, 7)
    for a in (r.t, r.pose, r.velocity, r.acceleration):
        assert a.dtype == np.float64 and a.flags.c_contiguous
    assert len(r) == 37
    assert r.t[0] == 0.0 and r.t[-1] == r.duration == r.waypoint_times[-1]
    np.testing.assert_allclose(r.pose[-1, :3], WAYPOINTS[-1, :3], atol=1e-12)
    assert r.pose[0, 6] >= 0.0  # the first quaternion has w >= 0


def test_the_figures_are_attributes_and_the_clis_dict():
    r = s.generate(waypoints=WAYPOINTS, max_linear_velocity=0.5)
    assert r.max_linear_speed == pytest.approx(0.5, rel=1e-6)
    assert r.figures["max_linear_speed"] == r.max_linear_speed
    assert r.figures["duration"] == r.duration and r.figures["energy"] == r.energy
    assert list(r.figures)[:3] == ["duration", "length", "rotation_length"]
    assert r.length > np.sum(np.linalg.norm(np.diff(WAYPOINTS[:, :3], axis=0), axis=1)) - 1e-9


def test_every_spelling_of_the_waypoints_gives_the_same_motion():
    rows = s.generate(waypoints=WAYPOINTS)
    pairs = [(w[:3].tolist(), w[3:].tolist()) for w in WAYPOINTS]
    mappings = [{"position": w[:3].tolist(), "orientation": dict(zip("xyzw", w[3:]))} for w in WAYPOINTS]
    pose_array = {"header": {"frame_id": "map"}, "poses": mappings}
    for waypoints in (WAYPOINTS.tolist(), pairs, mappings, pose_array, np.asfortranarray(WAYPOINTS), tuple(map(tuple, WAYPOINTS))):
        other = s.generate(waypoints=waypoints)
        assert np.array_equal(other.pose, rows.pose) and np.array_equal(other.acceleration, rows.acceleration)


def test_a_dict_and_keywords_combine_and_a_field_given_twice_is_refused():
    a = s.generate({"waypoints": WAYPOINTS, "curve": "bspline"}, sample_count=11)
    b = s.generate(waypoints=WAYPOINTS, curve="bspline", sample_count=11)
    assert np.array_equal(a.pose, b.pose)
    with pytest.raises(TypeError, match="curve: given both"):
        s.generate({"waypoints": WAYPOINTS, "curve": "bspline"}, curve="bezier")


def test_empty_and_zero_fields_are_the_defaults():
    default = s.generate(waypoints=WAYPOINTS)
    spelled = s.generate(
        waypoints=WAYPOINTS, curve="interpolating", geometry="double_geodesic", end_condition="natural",
        parameterization="chord", rotation_scale=1.0, timing="stretch", sample_count=100,
    )
    empty = s.generate(waypoints=WAYPOINTS, curve="", geometry="", degree=0, duration=0.0, sample_count=0, times=[])
    for other in (spelled, empty):
        assert np.array_equal(other.pose, default.pose) and other.duration == default.duration


@pytest.mark.parametrize("geometry", ["double_geodesic", "screw"])
@pytest.mark.parametrize("curve", FAMILIES)
def test_q_and_minus_q_give_identical_results(curve, geometry):
    flipped = WAYPOINTS.copy()
    flipped[1::2, 3:] *= -1.0
    a = s.generate(waypoints=WAYPOINTS, curve=curve, geometry=geometry, sample_count=51)
    b = s.generate(waypoints=flipped, curve=curve, geometry=geometry, sample_count=51)
    for name in ("t", "pose", "velocity", "acceleration", "waypoint_times"):
        assert np.array_equal(getattr(a, name), getattr(b, name)), name
    assert a.figures == b.figures
    # The control poses are the waypoints (or built from them) as given: the same rotations.
    same_sign = np.sign(np.sum(a.control_poses[:, 3:] * b.control_poses[:, 3:], axis=1))[:, None]
    assert np.array_equal(a.control_poses[:, 3:], same_sign * b.control_poses[:, 3:])


def test_arrays_own_their_memory_after_the_answer_is_gone():
    pose = s.generate(waypoints=WAYPOINTS, sample_count=1000).pose
    assert pose.shape == (1000, 7) and np.all(np.isfinite(pose))
    assert np.allclose(np.linalg.norm(pose[:, 3:], axis=1), 1.0)


def test_the_timed_motion_evaluates_between_samples():
    r = s.generate(waypoints=WAYPOINTS, max_linear_velocity=0.4, sample_count=21)
    at = r.evaluate(r.t)
    assert np.array_equal(at.pose, r.pose) and np.array_equal(at.velocity, r.velocity)
    pose, velocity, acceleration = r.evaluate([r.duration / 3])
    assert pose.shape == (1, 7) and velocity.shape == (1, 6) and acceleration.shape == (1, 6)
    with pytest.raises(s.InvalidInputError, match=r"^t\[1\]: .* is outside the motion"):
        r.evaluate([0.0, r.duration * 1.5])


def test_the_gil_is_released_while_the_planner_works():
    waypoints = np.zeros((1000, 7))
    waypoints[:, 0] = np.arange(1000) * 0.01
    waypoints[:, 1] = np.sin(np.arange(1000) * 0.1)
    waypoints[:, 6] = 1.0
    done = threading.Event()

    def work():
        for _ in range(3):
            s.generate(waypoints=waypoints, sample_count=100000)
        done.set()

    worker = threading.Thread(target=work)
    worker.start()
    spins = 0
    while not done.is_set():
        spins += 1
    worker.join()
    # Holding the GIL, the worker would let this loop run only between its calls (a handful of
    # switches); released, the loop runs throughout the ~0.3 s of planning.
    assert spins > 10000


def test_the_request_given_is_not_changed():
    request = {"waypoints": WAYPOINTS, "curve": "bspline"}
    s.generate(request, sample_count=5)
    s.generate(request, sample_count=6)
    assert sorted(request) == ["curve", "waypoints"]
    curve = s.bspline(WAYPOINTS)
    curve.fields["degree"] = 1
    assert "degree" not in curve.fields
