"""se3_interpolation from Python: the planner of the ~generate service and of se3_interpolate,
its curves and the groups' exp/log, on numpy arrays, without ROS (docs/python.md).

The compiled core is the extension module se3_interpolation._core (pybind11 over the C++ core
library, which links Eigen only). In a catkin workspace this package shares its name with the
generated messages, which stay importable beside it: se3_interpolation.msg, .srv, .cfg.

    import se3_interpolation as s
    motion = s.generate(waypoints=[[0, 0, 0, 0, 0, 0, 1], [1, 0, 0, 0, 0, 0.7071, 0.7071]])
    motion.t, motion.pose, motion.velocity, motion.acceleration   # numpy arrays
"""

from se3_interpolation._core import (  # noqa: F401 (the package's API)
    CURVE_FAMILIES,
    CURVE_FIELDS,
    REQUEST_FIELDS,
    ConvergenceError,
    Curve,
    InterpolationError,
    InvalidInputError,
    LimitExceededError,
    NonUniqueGeodesicError,
    Samples,
    Trajectory,
    generate,
    geodesic,
    make_curve,
    se3_exp,
    se3_log,
    so3_exp,
    so3_log,
)


def _timed(self, **fields):
    """The curve timed and sampled by generate(): its curve fields with the timing and sampling
    fields given here (timing, max_* bounds, speed, sample_count, ...). Returns a Trajectory."""
    return generate(self.fields, **fields)


Curve.timed = _timed


def _family_builder(name):
    def build(waypoints, **fields):
        return make_curve(name, waypoints, **fields)

    build.__name__ = build.__qualname__ = name
    build.__doc__ = (
        f"The untimed '{name}' curve through (or controlled by) waypoints: make_curve('{name}', "
        "waypoints, **fields), with the request's curve fields (CURVE_FIELDS). Returns a Curve."
    )
    return build


# One builder per registered curve family (interpolating, bspline, fit, ...), named after it.
for _name in CURVE_FAMILIES:
    globals()[_name] = _family_builder(_name)
del _name
