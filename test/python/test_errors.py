"""Errors are Python's: a bad request raises the core's error class (a ValueError) with the message
the service and the CLI give, naming the field and index; wrong types and shapes raise TypeError or
ValueError naming the argument; no input crashes the interpreter."""

import numpy as np
import pytest

import se3_interpolation as s
from conftest import WAYPOINTS, as_yaml_request

W = WAYPOINTS.tolist()

# Bad requests the CLI reads the same way (YAML of the same values): the module's message must be
# the CLI's, which is the service's (scripts, docs/command_line.md "Errors").
SAME_AS_CLI = {
    "unknown curve": {"waypoints": W, "curve": "splin"},
    "unknown field": {"waypoints": W, "curvee": "bspline"},
    "times not increasing": {"waypoints": W, "times": [0, 1, 1, 2]},
    "times count": {"waypoints": W, "times": [0, 1]},
    "quaternion norm": {"waypoints": W[:1] + [[1, 0, 0, 0, 0, 0, 2]]},
    "antipodal": {"waypoints": [[0, 0, 0, 0, 0, 0, 1], [0, 0, 0, 1, 0, 0, 0]], "curve": "piecewise_geodesic"},
    "one waypoint": {"waypoints": W[:1]},
    "degree range": {"waypoints": W, "curve": "bspline", "degree": 300},
    "degree too high": {"waypoints": W, "curve": "bspline", "degree": 5},
    "knots length": {"waypoints": W, "curve": "bspline", "knots": [0, 1, 2]},
    "knots elsewhere": {"waypoints": W, "curve": "hermite", "knots": [0, 0, 0, 0, 1, 1, 1, 1]},
    "twist length": {"waypoints": W, "start_velocity": {"linear": [1, 2]}},
    "unknown twist key": {"waypoints": W, "end_velocity": {"linear": [0, 0, 0], "rotational": [0, 0, 1]}},
    "position missing": {"waypoints": [{"orientation": [0, 0, 0, 1]}, {"position": [1, 0, 0]}]},
    "unknown output": {"waypoints": W, "outputs": ["path", "pth"]},
    "frame id": {"waypoints": W, "child_frame_id": "/tool"},
    "sample limit": {"waypoints": W, "sample_count": 10_000_000},
    "negative bound": {"waypoints": W, "max_linear_velocity": -1.0},
    "nan duration": {"waypoints": W, "duration": float("nan")},
    "sample time outside": {"waypoints": W, "times": [0, 1, 2, 3], "sample_times": [0, 4]},
    "unknown timing": {"waypoints": W, "timing": "fastest"},
    "missing bound": {"waypoints": W, "timing": "time_optimal"},
    "fit without times": {"waypoints": W, "curve": "fit"},
}


@pytest.mark.parametrize("case", sorted(SAME_AS_CLI))
def test_the_message_is_the_clis(case, run_cli):
    request = SAME_AS_CLI[case]
    cli = run_cli(as_yaml_request(request))
    assert cli.status == 2
    with pytest.raises(s.InterpolationError) as raised:
        s.generate(request)
    assert str(raised.value) == cli.error
    assert isinstance(raised.value, ValueError)


def test_the_error_classes_are_the_cores_and_value_errors():
    for name in ("InvalidInputError", "NonUniqueGeodesicError", "ConvergenceError", "LimitExceededError"):
        cls = getattr(s, name)
        assert issubclass(cls, s.InterpolationError) and issubclass(cls, ValueError)
    with pytest.raises(s.InvalidInputError, match=r"^times\[2\]: "):
        s.generate(waypoints=W, times=[0, 1, 1, 2])
    with pytest.raises(s.NonUniqueGeodesicError, match=r"^waypoints\[0\] and waypoints\[1\]: "):
        s.generate(**SAME_AS_CLI["antipodal"])
    with pytest.raises(s.LimitExceededError, match=r"^sample_count: .*\(max_samples\)"):
        s.generate(**SAME_AS_CLI["sample limit"])


@pytest.mark.parametrize(
    "fields, error, message",
    [
        ({"duration": "1"}, TypeError, r"^duration: expected a number, got str"),
        ({"duration": True}, TypeError, r"^duration: expected a number, got bool"),
        ({"degree": 3.0}, TypeError, r"^degree: expected an integer, got float"),
        ({"curve": 3}, TypeError, r"^curve: expected a string, got int"),
        ({"times": [0, "a", 2, 3]}, TypeError, r"^times\[1\]: expected a number, got str"),
        ({"times": np.zeros((2, 2))}, ValueError, r"^times: expected a 1-D list of numbers, got shape \(2, 2\)"),
        ({"publish": 1}, TypeError, r"^publish: expected True or False"),
        ({"start_state": [1, 2]}, TypeError, r"^start_state: expected \{pose"),
        ({"velocities": np.zeros((4, 5))}, ValueError, r"^velocities: expected an \(N, 6\) array"),
        ({"from_current": True}, ValueError, r"^from_current: the Python module plays no trajectory"),
        ({"waypoint_frames": ["tool0"]}, ValueError, r"^waypoint_frames: the Python module has no TF"),
    ],
)
def test_wrong_types_and_shapes_name_the_field(fields, error, message):
    with pytest.raises(error, match=message):
        s.generate(waypoints=W, **fields)


@pytest.mark.parametrize(
    "waypoints, error, message",
    [
        (np.zeros((3, 6)), ValueError, r"^waypoints: expected an \(N, 7\) array .*got shape \(3, 6\)"),
        (np.zeros(7), ValueError, r"^waypoints: expected an \(N, 7\) array .*got shape \(7,\)"),
        (np.array([["a"] * 7] * 2), TypeError, r"^waypoints: expected a numeric array, got dtype"),
        (np.zeros((2, 7), dtype=complex), TypeError, r"^waypoints: expected a numeric array"),
        ([[0, 0, 0, 0, 0, 0, 1], ([1, 0], [0, 0, 0, 1])], ValueError, r"^waypoints\[1\]\.position: expected 3"),
        ([[0, 0, 0, 0, 0, 0, 1], [1, 0, 0]], ValueError, r"^waypoints\[1\]: expected 7 numbers"),
        ([[0, 0, 0, 0, 0, 0, 1], [1, 0]], ValueError, r"^waypoints\[1\]: expected 7 numbers .*, got 2"),
        ([[0, 0, 0, 0, 0, 0, 1], "pose"], TypeError, r"^waypoints\[1\]: expected \[x, y, z, qx"),
        ("poses", TypeError, r"^waypoints: expected an \(N, 7\) array or a list of poses, got str"),
        ({"poses": W, "frame": "map"}, ValueError, r"^waypoints\.frame: unknown field"),
    ],
)
def test_bad_waypoints_name_the_argument(waypoints, error, message):
    with pytest.raises(error, match=message):
        s.generate(waypoints=waypoints)


def test_a_request_that_is_not_a_dict_is_a_type_error():
    with pytest.raises(TypeError, match="^request: expected a dict"):
        s.generate([W])
    with pytest.raises(TypeError, match="keys must be strings|request key: expected a string"):
        s.generate({1: W})


JUNK = [
    None, 0, -1, 2**80, 1e308, float("inf"), float("nan"), "", "x" * 5000, b"bytes", True, [], [[]], [None],
    {}, {"x": 1}, [1, 2, 3], [[1, 2], [3]], np.array([]), np.zeros((0, 7)), np.zeros((2, 7, 1)),
    np.array([1 + 2j]), np.array([object()]), np.full((2, 7), np.nan), object(), [[1e308] * 7] * 3,
    [{"position": [0, 0, 0]}] * 3, {"poses": None}, {"linear": "x"}, ([0, 0, 0], None),
]


def test_junk_in_any_field_raises_a_python_error_and_never_crashes():
    rng = np.random.default_rng(53)
    base = {"waypoints": W, "sample_count": 5}
    fields = list(s.REQUEST_FIELDS)
    for _ in range(3000):
        request = dict(base)
        for field in rng.choice(fields, size=rng.integers(1, 4), replace=False):
            request[str(field)] = JUNK[rng.integers(len(JUNK))]
        try:
            s.generate(request, max_work_seconds=0.2)
        except (TypeError, ValueError):
            pass


CHOICES = {
    "curve": list(s.CURVE_FAMILIES) + ["", "spline"],
    "geometry": ["", "double_geodesic", "screw"],
    "timing": ["", "stretch", "time_optimal", "constant_speed"],
    "end_condition": ["", "natural", "clamped", "start"],
    "parameterization": ["", "chord", "uniform", "centripetal"],
}
NUMBERS = [0.0, 1e-12, 0.3, 1.0, 4.0, 1e12, -1.0, float("nan"), float("inf")]
NUMBER_FIELDS = ["duration", "rotation_scale", "max_linear_velocity", "max_angular_velocity", "max_linear_acceleration",
                 "max_angular_acceleration", "max_linear_jerk", "max_angular_jerk", "speed", "blend_radius",
                 "sample_period", "control_period", "smoothing"]


def random_request(rng):
    """Plausible requests with random choices, extreme numbers, repeated and antipodal waypoints."""
    n = int(rng.integers(1, 7))
    waypoints = np.hstack([rng.normal(size=(n, 3)), rng.normal(size=(n, 4))])
    waypoints[:, 3:] /= np.linalg.norm(waypoints[:, 3:], axis=1)[:, None]
    if n > 2 and rng.random() < 0.2:
        waypoints[2] = waypoints[1]
    if n > 1 and rng.random() < 0.1:
        waypoints[1, 3:] = [1, 0, 0, 0]
        waypoints[0, 3:] = [0, 0, 0, 1]
    request = {"waypoints": waypoints, "sample_count": int(rng.choice([0, 2, 7, 50]))}
    for field, names in CHOICES.items():
        if rng.random() < 0.5:
            request[field] = str(rng.choice(names))
    for field in rng.choice(NUMBER_FIELDS, size=int(rng.integers(0, 5)), replace=False):
        request[str(field)] = float(rng.choice(NUMBERS))
    if rng.random() < 0.3:
        request["times"] = np.cumsum(rng.uniform(-0.1, 2.0, size=n))
    if rng.random() < 0.2:
        request["degree"] = int(rng.integers(0, 6))
    return request


def test_random_requests_are_served_with_finite_samples_or_refused():
    rng = np.random.default_rng(5300)
    served = 0
    for _ in range(2000):
        request = random_request(rng)
        try:
            r = s.generate(request, max_work_seconds=0.2)
        except ValueError:
            continue
        served += 1
        assert len(r.t) >= 2 and r.pose.shape == (len(r.t), 7)
        for a in (r.t, r.pose, r.velocity, r.acceleration):
            assert np.all(np.isfinite(a))
        assert np.all(np.diff(r.t) >= 0.0)
    assert served > 200  # enough of them are valid for the checks above to mean something


def test_a_huge_sample_count_meets_the_planners_refusal_not_an_allocation():
    with pytest.raises(s.LimitExceededError, match="^sample_count: 4294967295 samples"):
        s.generate(waypoints=W, sample_count=4294967295, max_samples=10**15)
