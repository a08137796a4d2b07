"""The package: the compiled core beside the generated messages, which keep importing, and no ROS
library in the module."""

import subprocess

import se3_interpolation as s


def test_the_generated_messages_import_beside_the_module():
    import se3_interpolation.msg as msg
    import se3_interpolation.srv as srv

    assert hasattr(srv, "GenerateTrajectory") and hasattr(srv, "GenerateTrajectoryRequest")
    assert hasattr(msg, "GenerationStatus") and hasattr(msg, "FollowTrajectoryAction")
    assert callable(s.generate)


def test_the_module_links_the_core_and_no_ros_library():
    libraries = subprocess.run(["ldd", s._core.__file__], capture_output=True, text=True, check=True).stdout
    names = [line.split()[0] for line in libraries.splitlines() if line.strip()]
    assert "libse3_interpolation_core.so" in names
    ros = [n for n in names if n.startswith(("libroscpp", "librosbag", "librostime", "libtf2", "libactionlib",
                                             "libse3_interpolation_ros", "libyaml-cpp", "libboost"))]
    assert ros == []


def test_the_api_lists_its_fields_and_families():
    assert s.REQUEST_FIELDS[0] == "waypoints" and "start_state" in s.REQUEST_FIELDS
    assert set(s.CURVE_FIELDS) < set(s.REQUEST_FIELDS) and "timing" not in s.CURVE_FIELDS
    assert s.CURVE_FAMILIES[:2] == ["piecewise_geodesic", "bezier"]
