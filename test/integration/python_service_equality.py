#!/usr/bin/python3
"""The docs' example requests (docs/examples/*.yaml; fit with its recording) through the Python
module and through the node's ~generate service: the same poses, velocities and accelerations bit
for bit, the sample times within time_from_start's 1 ns (a ros::Duration), the same figures. Run
by rostest (test/integration/python_service_equality.test), which starts the node."""
import glob
import os
import unittest

import numpy as np
import rospy
import rostest
import yaml
from geometry_msgs.msg import Pose, Twist

import se3_interpolation as s
from se3_interpolation.srv import GenerateTrajectory, GenerateTrajectoryRequest

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
EXAMPLES = os.path.join(ROOT, "docs", "examples")
SERVICE = "/se3_interpolation_node/generate"
FIGURES = ["duration", "length", "rotation_length", "max_linear_speed", "max_angular_speed",
           "peak_linear_acceleration", "peak_angular_acceleration", "peak_linear_jerk", "peak_angular_jerk",
           "energy", "constant_speed_start", "constant_speed_end", "residual_linear", "residual_angular"]


def example(path):
    """The module's request of a docs example (fit: with the recording's waypoints and times)."""
    with open(path) as f:
        request = yaml.safe_load(f)
    if request.get("curve") == "fit":
        recording = np.loadtxt(os.path.join(EXAMPLES, "fit_recording.csv"), delimiter=",", skiprows=1)
        request.update(times=recording[:, 0].tolist(), waypoints=recording[:, 1:8].tolist())
    return request


def pose_message(waypoint):
    """A geometry_msgs/Pose of a waypoint row [x, y, z, qx, qy, qz, qw] or {position, orientation}."""
    if isinstance(waypoint, dict):
        waypoint = list(waypoint["position"]) + list(waypoint.get("orientation", [0, 0, 0, 1]))
    p = Pose()
    p.position.x, p.position.y, p.position.z = waypoint[:3]
    p.orientation.x, p.orientation.y, p.orientation.z, p.orientation.w = waypoint[3:]
    return p


def service_request(request):
    """The GenerateTrajectory request of a module request (the examples' fields are the service's)."""
    r = GenerateTrajectoryRequest()
    for name, value in request.items():
        if name == "waypoints":
            r.waypoints.header.frame_id = "map"
            r.waypoints.poses = [pose_message(w) for w in value]
        else:
            setattr(r, name, value)
    return r


def twist_rows(twists):
    return [[t.linear.x, t.linear.y, t.linear.z, t.angular.x, t.angular.y, t.angular.z] for t in twists]


class PythonServiceEquality(unittest.TestCase):
    def test_examples_are_found(self):
        self.assertGreaterEqual(len(glob.glob(os.path.join(EXAMPLES, "*.yaml"))), 5)

    def test_the_module_equals_the_service(self):
        rospy.wait_for_service(SERVICE, timeout=60)
        generate = rospy.ServiceProxy(SERVICE, GenerateTrajectory)
        for path in sorted(glob.glob(os.path.join(EXAMPLES, "*.yaml"))):
            request = example(path)
            # An arm's example (joint_seed) needs a node with that arm (test/integration/node_arm.test).
            if "joint_seed" in request:
                continue
            with self.subTest(example=os.path.basename(path)):
                mine = s.generate(request)
                answer = generate(service_request(request))
                self.assertTrue(answer.success, answer.message)
                points = answer.trajectory.points
                self.assertEqual(len(points), len(mine.t))
                pose = [[p.transforms[0].translation.x, p.transforms[0].translation.y, p.transforms[0].translation.z,
                         p.transforms[0].rotation.x, p.transforms[0].rotation.y, p.transforms[0].rotation.z,
                         p.transforms[0].rotation.w] for p in points]
                self.assertTrue(np.array_equal(np.array(pose), mine.pose))
                self.assertTrue(np.array_equal(np.array(twist_rows(p.velocities[0] for p in points)), mine.velocity))
                self.assertTrue(np.array_equal(np.array(twist_rows(p.accelerations[0] for p in points)),
                                               mine.acceleration))
                times = np.array([p.time_from_start.to_sec() for p in points])
                self.assertLessEqual(np.abs(times - mine.t).max(), 0.6e-9)
                for figure in FIGURES:
                    self.assertEqual(getattr(answer, figure), getattr(mine, figure), figure)


if __name__ == "__main__":
    rospy.init_node("python_service_equality")
    rostest.rosrun("se3_interpolation", "python_service_equality", PythonServiceEquality)
