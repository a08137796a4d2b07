#!/usr/bin/python3
"""Minimal rospy client of se3_interpolation_node's ~generate service (the README's example).

Run with the node up: rosrun se3_interpolation example_client.py
"""
import math

import rospy
from geometry_msgs.msg import Pose
from se3_interpolation.srv import GenerateTrajectory, GenerateTrajectoryRequest


def pose(x, y, z, yaw):
    p = Pose()
    p.position.x, p.position.y, p.position.z = x, y, z
    p.orientation.z, p.orientation.w = math.sin(yaw / 2), math.cos(yaw / 2)
    return p


rospy.init_node("se3_interpolation_example")
rospy.wait_for_service("/se3_interpolation_node/generate")
generate = rospy.ServiceProxy("/se3_interpolation_node/generate", GenerateTrajectory)

req = GenerateTrajectoryRequest()
req.waypoints.header.frame_id = "map"
req.waypoints.poses = [pose(0, 0, 0, 0), pose(1, 0, 0.5, 1.0), pose(1, 1, 1, 2.0), pose(0, 1.5, 1, 3.0)]
req.curve = "bspline"
req.geometry = "screw"
req.max_linear_velocity = 0.5  # m/s: time is stretched until no sample exceeds it
req.sample_period = 0.1        # s
req.publish = True             # also publish ~path, ~trajectory, ~markers and TF

res = generate(req)
if not res.success:
    raise SystemExit("generation failed: " + res.message)
print("duration %.3f s, length %.3f m, peak speed %.3f m/s, %d samples"
      % (res.duration, res.length, res.max_linear_speed, len(res.trajectory.points)))
point = res.trajectory.points[len(res.trajectory.points) // 2]
print("mid-point at t = %.2f s: position %s, velocity %s"
      % (point.time_from_start.to_sec(), point.transforms[0].translation, point.velocities[0].linear))
