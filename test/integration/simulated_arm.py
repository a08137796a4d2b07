#!/usr/bin/env python3
"""A simulated arm for the action tests: it follows the setpoint of se3_interpolation_node's
~command (geometry_msgs/PoseStamped) and broadcasts where it "is" on TF as the frame
~measured_frame (what a robot driver publishes as its measured tool frame), in the command's frame.

Its behaviour is set at run time on ~mode (std_msgs/String), so that one test run can show every
outcome of the action's tolerances; each mode, once applied, is echoed on the latched ~applied
(std_msgs/String), so that a test waits for the arm instead of guessing how late it runs:
  "follow"       the measured frame is the commanded pose (a perfect controller)
  "freeze"       the measured frame stays where it is (a stalled arm)
  "offset D"     the commanded pose shifted by D m along the frame's x axis (a biased arm)
It broadcasts at ~rate Hz (default 100) once a command has arrived. Following (and biased), the
arm is where it was commanded when it was commanded: its transform carries the command's stamp, as
a driver stamps a measurement with the instant it was taken, so that this process running late (a
loaded machine) delays the measurement without moving it off the path; a command already broadcast
is not broadcast again (TF would drop the repeated stamp). Frozen, it is stamped now: a live
driver of a stalled arm.
"""
import threading

import rospy
import tf2_ros
from geometry_msgs.msg import PoseStamped, TransformStamped
from std_msgs.msg import String


class SimulatedArm:
    def __init__(self):
        self.frame = rospy.get_param("~measured_frame", "measured_tool")
        self.lock = threading.Lock()
        self.mode = "follow"
        self.offset = 0.0
        self.command = None
        self.held = None
        self.broadcast_stamp = None
        self.broadcaster = tf2_ros.TransformBroadcaster()
        self.applied = rospy.Publisher("~applied", String, queue_size=1, latch=True)
        self.applied.publish(String(data=self.mode))
        rospy.Subscriber("command", PoseStamped, self.on_command, queue_size=10)
        rospy.Subscriber("~mode", String, self.on_mode, queue_size=10)
        rospy.Timer(rospy.Duration(1.0 / rospy.get_param("~rate", 100.0)), self.broadcast)

    def on_command(self, msg):
        with self.lock:
            self.command = msg

    def on_mode(self, msg):
        words = msg.data.split()
        with self.lock:
            self.held = self.command if words[0] == "freeze" else None
            self.mode = words[0]
            self.offset = float(words[1]) if words[0] == "offset" else 0.0
        self.applied.publish(msg)
        rospy.loginfo("simulated arm: %s", msg.data)

    def broadcast(self, _event):
        with self.lock:
            frozen = self.mode == "freeze"
            shown = self.held if frozen else self.command
            offset = self.offset
            if shown is None or (not frozen and shown.header.stamp == self.broadcast_stamp):
                return
            stamp = rospy.Time.now() if frozen else shown.header.stamp
            self.broadcast_stamp = stamp
        t = TransformStamped()
        t.header.stamp = stamp
        t.header.frame_id = shown.header.frame_id
        t.child_frame_id = self.frame
        t.transform.translation.x = shown.pose.position.x + offset
        t.transform.translation.y = shown.pose.position.y
        t.transform.translation.z = shown.pose.position.z
        t.transform.rotation = shown.pose.orientation
        self.broadcaster.sendTransform(t)


if __name__ == "__main__":
    rospy.init_node("simulated_arm")
    SimulatedArm()
    rospy.spin()
