#!/usr/bin/python3
"""rospy client timing se3_interpolation_node's ~generate service for a large request.

The same request as bench/service_latency.cpp (the roscpp client): N waypoints on the same
deterministic walk, an `interpolating` double-geodesic curve, M samples. Per repetition: the round
trip of the service call (rospy's serialisation of the request, the node, the transport and
rospy's deserialisation of the response). Afterwards, on the last response: its deserialisation
alone (genpy's deserialize of the serialised bytes). scripts/service_latency.sh runs it.

Usage: service_latency.py [--service NAME] [--waypoints N] [--samples M] [--repetitions R]
                          [--outputs path,trajectory]   (empty: the service's default, both)
"""
import argparse
import io
import math
import time

import rospy
from geometry_msgs.msg import Pose
from se3_interpolation.srv import GenerateTrajectory, GenerateTrajectoryRequest, GenerateTrajectoryResponse


def waypoint(i):
    """Waypoint i: the formula of bench/service_latency.cpp (q = q_z(yaw) q_x(roll))."""
    p = Pose()
    p.position.x, p.position.y, p.position.z = 0.3 * i, math.sin(0.5 * i), 0.2 * math.cos(0.3 * i)
    yaw, roll = 0.4 * i, 0.3 * math.sin(0.7 * i)
    cy, sy, cr, sr = math.cos(0.5 * yaw), math.sin(0.5 * yaw), math.cos(0.5 * roll), math.sin(0.5 * roll)
    p.orientation.w, p.orientation.x, p.orientation.y, p.orientation.z = cy * cr, cy * sr, sy * sr, sy * cr
    return p


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--service", default="/se3_interpolation_node/generate")
    parser.add_argument("--waypoints", type=int, default=1000)
    parser.add_argument("--samples", type=int, default=100000)
    parser.add_argument("--repetitions", type=int, default=3)
    parser.add_argument("--outputs", default="")
    args = parser.parse_args(rospy.myargv()[1:])

    rospy.init_node("se3_service_latency_py", anonymous=True)
    rospy.wait_for_service(args.service, timeout=30.0)
    generate = rospy.ServiceProxy(args.service, GenerateTrajectory, persistent=True)

    req = GenerateTrajectoryRequest()
    req.waypoints.header.frame_id = "map"
    req.waypoints.poses = [waypoint(i) for i in range(args.waypoints)]
    req.curve = "interpolating"
    req.geometry = "double_geodesic"
    req.sample_count = args.samples
    req.outputs = [o for o in args.outputs.split(",") if o]

    round_trips = []
    res = None
    for _ in range(max(1, args.repetitions)):
        start = time.monotonic()
        res = generate(req)
        round_trips.append(time.monotonic() - start)
        if not res.success:
            raise SystemExit("call failed: " + res.message)

    buf = io.BytesIO()
    res.serialize(buf)
    data = buf.getvalue()
    start = time.monotonic()
    GenerateTrajectoryResponse().deserialize(data)
    deserialise = time.monotonic() - start

    round_trips.sort()
    print("rospy client: %d waypoints, %d samples, outputs [%s]: path %d poses, trajectory %d points, "
          "response %.1f MB" % (args.waypoints, args.samples, args.outputs, len(res.path.poses),
                                len(res.trajectory.points), len(data) / 1e6))
    print("  round trip: median %.3f s, min %.3f s over %d calls" %
          (round_trips[len(round_trips) // 2], round_trips[0], len(round_trips)))
    print("  rospy deserialisation of the response alone: %.3f s" % deserialise)


if __name__ == "__main__":
    main()
