#!/usr/bin/python3
"""Demo client: sends the example waypoints of config/demo_waypoints.yaml to
se3_interpolation_node's ~generate service for each curve and geometry, prints a summary
table, and publishes the last trajectory (path, markers, TF) for rviz.

Private parameters: ~waypoints_file (path), ~service (default /se3_interpolation_node/generate),
~curves (list), ~geometries (list), ~duration (s), ~summary_file (also write the summary there).
"""
import sys

import rospy
import yaml
from geometry_msgs.msg import Pose, PoseArray

from se3_interpolation.srv import GenerateTrajectory, GenerateTrajectoryRequest


def load_waypoints(path):
    with open(path) as f:
        doc = yaml.safe_load(f)
    poses = PoseArray()
    poses.header.frame_id = doc.get("frame_id", "map")
    for w in doc["waypoints"]:
        p = Pose()
        p.position.x, p.position.y, p.position.z = w["position"]
        p.orientation.x, p.orientation.y, p.orientation.z, p.orientation.w = w["orientation"]
        poses.poses.append(p)
    return poses


def main():
    rospy.init_node("se3_interpolation_demo")
    path = rospy.get_param("~waypoints_file")
    service = rospy.get_param("~service", "/se3_interpolation_node/generate")
    curves = rospy.get_param("~curves", ["piecewise_geodesic", "bezier", "bspline", "hermite", "interpolating", "blended"])
    geometries = rospy.get_param("~geometries", ["double_geodesic", "screw"])
    duration = float(rospy.get_param("~duration", 6.0))
    summary_file = rospy.get_param("~summary_file", "")
    waypoints = load_waypoints(path)
    rospy.wait_for_service(service, timeout=30.0)
    generate = rospy.ServiceProxy(service, GenerateTrajectory)

    lines = []

    def say(text):
        lines.append(text)
        print(text)

    say("se3_interpolation demo: %d waypoints from %s, %.1f s" % (len(waypoints.poses), path, duration))
    header = "%-20s %-16s %8s %10s %10s %11s %13s %15s" % (
        "curve", "geometry", "samples", "length[m]", "rot[rad]", "v_max[m/s]", "w_max[rad/s]", "energy[m2/s3]")
    say(header)
    say("-" * len(header))
    failures = 0
    for i, curve in enumerate(curves):
        for j, geometry in enumerate(geometries):
            req = GenerateTrajectoryRequest()
            req.waypoints = waypoints
            req.curve = curve
            req.geometry = geometry
            req.duration = duration
            req.sample_count = 200
            req.publish = (i == len(curves) - 1 and j == len(geometries) - 1)
            res = generate(req)
            if not res.success:
                failures += 1
                say("%-20s %-16s FAILED: %s" % (curve, geometry, res.message))
                continue
            say("%-20s %-16s %8d %10.4f %10.4f %11.4f %13.4f %15.4f" % (
                curve, geometry, len(res.path.poses), res.length, res.rotation_length,
                res.max_linear_speed, res.max_angular_speed, res.energy))
    say("length: translation path length; rot: rotation angle travelled; v_max, w_max: peak linear and")
    say("angular speed; energy: integral of |p''|^2 + rho^2 |w'|^2 dt over the smooth pieces (Crouch et al.")
    say("eq. 32, rho = rotation_scale = 1 m/rad; docs/timing.md \"Sampling and figures\"). The velocity jumps of")
    say("piecewise_geodesic at the waypoints are not counted, so with double_geodesic (straight lines and")
    say("fixed-axis turns at constant rates) its energy is 0; screw segments are helices, accelerated.")
    say("Published the last trajectory on ~path, ~trajectory, ~markers and TF frame 'interpolated'.")
    sys.stdout.flush()
    if summary_file:
        with open(summary_file, "w") as f:
            f.write("\n".join(lines) + "\n")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
