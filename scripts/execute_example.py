#!/usr/bin/python3
"""Execute motions with the node's action ~follow_trajectory: send, replace, cancel.

usage: execute_example.py [--node NAME] [--command-topic TOPIC] [--plot FILE.png]

Against a running se3_interpolation_node with velocity, acceleration and jerk bounds set (e.g.
`roslaunch docs/examples/execute.launch`), in the frame `map`:
  1. generates a motion with ~generate (from_current, time_optimal, not published) and sends it as
     a goal, printing its feedback at about 2 Hz;
  2. half-way through, generates again from the frame's current motion (from_current) toward other
     waypoints and sends that as a new goal: it replaces the first at its stamp without a jump
     (the first ends PREEMPTED), and runs to its end (SUCCEEDED);
  3. sends a third goal from where the second stopped and cancels it half-way: the frame comes to
     rest along its path (PREEMPTED); prints where (the result's stopped_at).
Exits 0 when the three goals end PREEMPTED, SUCCEEDED and PREEMPTED, 1 when one ends otherwise,
2 when the node cannot be reached or a generation fails.

--plot FILE.png records the node's setpoint ~command (geometry_msgs/PoseStamped; by default the
node's PoseStamped publication found through the master, wherever it is remapped) and draws the
commanded position and speed (finite differences of the commands) against time, with the
replacement and the cancel marked (docs/execute_example.png). Needs Debian's python3-matplotlib
(the shebang).
"""
import argparse
import math
import sys
import threading

import actionlib
import rosgraph
import rospy
from actionlib_msgs.msg import GoalStatus
from geometry_msgs.msg import Pose, PoseStamped
from se3_interpolation.msg import FollowTrajectoryAction, FollowTrajectoryGoal
from se3_interpolation.srv import GenerateTrajectory, GenerateTrajectoryRequest

FRAME = "map"
# The switch time of every request: its stamp, this far ahead of the call, so that the goal arrives
# before it (a goal generated with from_current must start where the frame is at its stamp).
LEAD = 0.5  # s
# Waypoints (x, y, z [m], yaw [rad]) of the three goals. Each goal starts where the frame is
# (from_current), so the first starts at its first waypoint only on a fresh node.
FIRST = [(0.0, 0.0, 0.4, 0.0), (0.5, 0.4, 0.5, 0.6), (1.0, 0.0, 0.4, 1.2)]
SECOND = [(0.6, -0.4, 0.6, 0.3), (0.0, -0.3, 0.4, -0.3)]
THIRD = [(0.4, 0.3, 0.8, 0.8), (1.0, 0.5, 0.4, 0.0)]
STATES = {getattr(GoalStatus, n): n for n in ("PENDING", "ACTIVE", "PREEMPTED", "SUCCEEDED", "ABORTED", "REJECTED",
                                              "PREEMPTING", "RECALLING", "RECALLED", "LOST")}


def pose(x, y, z, yaw):
    p = Pose()
    p.position.x, p.position.y, p.position.z = x, y, z
    p.orientation.z, p.orientation.w = math.sin(yaw / 2), math.cos(yaw / 2)
    return p


def fail(message, code=2):
    print("execute_example: " + message, file=sys.stderr)
    sys.exit(code)


class Goal:
    """One goal sent to ~follow_trajectory: its trajectory, its handle, its end and its feedback."""

    def __init__(self, name, trajectory, duration):
        self.name = name
        self.trajectory = trajectory
        self.duration = duration
        self.stamp = trajectory.header.stamp.to_sec()
        self.handle = None
        self.done = threading.Event()
        self.state = None
        self.result = None
        self.last_print = -1.0

    def on_transition(self, handle):
        if handle.get_comm_state() == actionlib.CommState.DONE and not self.done.is_set():
            self.state = handle.get_goal_status()
            self.result = handle.get_result()
            self.done.set()

    def on_feedback(self, _handle, feedback):
        # About 2 Hz of the node's ~feedback_rate; none before the goal's stamp (the replaced goal plays).
        if feedback.time_from_start < 0.0 or feedback.time_from_start < self.last_print + 0.5:
            return
        self.last_print = feedback.time_from_start
        p = feedback.desired.translation
        print("  %s  t = %5.2f s  desired (%6.3f, %6.3f, %6.3f) m  linear_error %.4f m"
              % (self.name, feedback.time_from_start, p.x, p.y, p.z, feedback.linear_error), flush=True)

    def wait(self, timeout):
        if not self.done.wait(timeout):
            fail("%s did not end within %.0f s" % (self.name, timeout), 1)
        return self.state


class CommandRecorder:
    """The setpoints of ~command: (stamp, x, y, z)."""

    def __init__(self, topic):
        self.lock = threading.Lock()
        self.samples = []
        self.sub = rospy.Subscriber(topic, PoseStamped, self.on_command, queue_size=1000)

    def on_command(self, msg):
        p = msg.pose.position
        with self.lock:
            self.samples.append((msg.header.stamp.to_sec(), p.x, p.y, p.z))


def command_topic(node):
    """The node's geometry_msgs/PoseStamped publication: ~command, wherever it is remapped."""
    master = rosgraph.Master("/execute_example")
    types = dict(master.getTopicTypes())
    for topic, publishers in master.getSystemState()[0]:
        if node in publishers and types.get(topic) == "geometry_msgs/PoseStamped":
            return topic
    return node + "/command"


class Example:
    def __init__(self, node):
        self.generate = rospy.ServiceProxy(node + "/generate", GenerateTrajectory)
        self.client = actionlib.ActionClient(node + "/follow_trajectory", FollowTrajectoryAction)

    def plan(self, name, waypoints):
        """A time-optimal rest-to-rest motion from the frame's state at now + LEAD through `waypoints`."""
        req = GenerateTrajectoryRequest()
        req.waypoints.header.frame_id = FRAME
        req.waypoints.header.stamp = rospy.Time.now() + rospy.Duration(LEAD)
        req.waypoints.poses = [pose(*w) for w in waypoints]
        req.timing = "time_optimal"  # within the node's ~max_* bounds
        req.from_current = True
        req.publish = False  # the goal moves the frame, not ~generate
        # Ten samples, and more wherever the goal's interpolation between them would stray from the
        # motion by over 0.1 mm or exceed a bound (docs/timing.md, "Samples a goal executes faithfully").
        req.sample_count = 10
        req.sample_tolerance = 1e-4
        req.outputs = ["trajectory"]
        res = self.generate(req)
        if not res.success:
            fail("generating %s failed: %s" % (name, res.message))
        print("%s: %d points over %.2f s, %.2f m" % (name, len(res.trajectory.points), res.duration, res.length))
        return Goal(name, res.trajectory, res.duration)

    def send(self, goal):
        goal.handle = self.client.send_goal(FollowTrajectoryGoal(trajectory=goal.trajectory),
                                            transition_cb=goal.on_transition, feedback_cb=goal.on_feedback)
        return goal


def sleep_until(t):
    rospy.sleep(max(0.0, t - rospy.Time.now().to_sec()))


def report(goal, expected):
    name = STATES.get(goal.state, str(goal.state))
    why = goal.result.error_string if goal.result else ""
    print("%s ended %s%s (expected %s)" % (goal.name, name, ": " + why if why else "", expected))
    return name == expected


def plot(path, samples, first, second, third, cancel_time, stopped_time):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    t0 = first.stamp
    t = [s[0] - t0 for s in samples]
    speed_t, speed = [], []
    for a, b in zip(samples, samples[1:]):
        dt = b[0] - a[0]
        if dt > 1e-6:
            speed_t.append(0.5 * (a[0] + b[0]) - t0)
            speed.append(math.sqrt((b[1] - a[1]) ** 2 + (b[2] - a[2]) ** 2 + (b[3] - a[3]) ** 2) / dt)

    def planned(goal):
        """The goal's planned positions and speeds against the same clock."""
        rows = []
        for p in goal.trajectory.points:
            tt = goal.stamp + p.time_from_start.to_sec() - t0
            v = p.velocities[0].linear
            rows.append((tt, p.transforms[0].translation, math.sqrt(v.x ** 2 + v.y ** 2 + v.z ** 2)))
        return rows

    fig, (ax_p, ax_v) = plt.subplots(2, 1, figsize=(12, 6.6), sharex=True)
    for i, axis in enumerate("xyz"):
        ax_p.plot(t, [s[1 + i] for s in samples], "C%d" % i, label=axis + " of ~command")
    for goal, color, label in ((first, "C1", "goal 1 as planned (replaced)"),
                               (third, "C3", "goal 3 as planned (cancelled)")):
        rows = planned(goal)
        for i, axis in enumerate("xyz"):
            ax_p.plot([r[0] for r in rows], [getattr(r[1], axis) for r in rows], "C%d:" % i, lw=1,
                      label="as planned: goals 1 and 3" if goal is first and axis == "x" else None)
        ax_v.plot([r[0] for r in rows], [r[2] for r in rows], ":", color=color, lw=1.4, label=label)
    ax_v.plot(speed_t, speed, "k", lw=1.3, label="|v| of ~command\n(finite differences)")

    # (instant, label, colour, label left of the line)
    marks = [(first.stamp, "goal 1 starts", "C2", False),
             (second.stamp, "goal 2 replaces goal 1\n(from_current: C2)", "C1", False),
             (second.stamp + second.duration, "goal 2\nsucceeds", "C2", True),
             (third.stamp, "goal 3\nstarts", "C2", False),
             (cancel_time, "goal 3\ncancelled", "C3", True),
             (stopped_time, "at rest", "C3", False)]
    top = max(speed) if speed else 1.0
    for when, text, color, left in marks:
        for ax in (ax_p, ax_v):
            ax.axvline(when - t0, color=color, lw=0.9, ls="--")
        ax_v.text(when - t0 + (-0.05 if left else 0.05), 1.42 * top, text, fontsize=8, color=color, va="top",
                  ha="right" if left else "left")
    ax_v.axvspan(cancel_time - t0, stopped_time - t0, color="C3", alpha=0.12,
                 label="smooth stop (within the\nacceleration bounds)")
    ax_p.set_ylabel("commanded position [m]")
    ax_p.legend(fontsize=8, loc="upper left", bbox_to_anchor=(1.01, 1.0))
    ax_p.set_title("~follow_trajectory: a goal, its replacement half-way, a third goal cancelled half-way "
                   "(~command at ~command_rate)", fontsize=10)
    ax_v.set_ylim(0, 1.45 * top)
    ax_v.set_ylabel("commanded speed [m/s]")
    ax_v.set_xlabel("t [s] since goal 1's stamp")
    ax_v.legend(fontsize=8, loc="upper left", bbox_to_anchor=(1.01, 1.0))
    fig.tight_layout()
    fig.savefig(path, dpi=90, bbox_inches="tight")
    print("wrote", path)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--node", default="/se3_interpolation_node", help="the node's name (default: %(default)s)")
    parser.add_argument("--command-topic", help="the node's ~command as remapped (default: found through the master)")
    parser.add_argument("--plot", metavar="FILE.png", help="record ~command and plot it")
    args = parser.parse_args(rospy.myargv()[1:])
    node = args.node.rstrip("/")

    rospy.init_node("execute_example", anonymous=True)
    try:
        rospy.wait_for_service(node + "/generate", timeout=30.0)
    except rospy.ROSException:
        fail("no service %s/generate (is the node running? roslaunch docs/examples/execute.launch)" % node)
    example = Example(node)
    if not example.client.wait_for_server(rospy.Duration(30.0)):
        fail("no action server %s/follow_trajectory" % node)
    recorder = None
    if args.plot:
        topic = args.command_topic or command_topic(node)
        print("recording ~command on", topic)
        recorder = CommandRecorder(topic)
        rospy.sleep(0.5)  # let the subscription connect

    # 1. A goal, with feedback.
    first = example.send(example.plan("goal 1", FIRST))
    # 2. Half-way through, a goal from the frame's current motion replaces it at its stamp.
    sleep_until(first.stamp + 0.45 * first.duration)
    second = example.send(example.plan("goal 2", SECOND))
    first.wait(10.0)
    ok = report(first, "PREEMPTED")
    second.wait(second.stamp - rospy.Time.now().to_sec() + second.duration + 10.0)
    ok = report(second, "SUCCEEDED") and ok
    # 3. A goal cancelled half-way: the frame stops along its path.
    third = example.send(example.plan("goal 3", THIRD))
    sleep_until(third.stamp + 0.5 * third.duration)
    cancel_time = rospy.Time.now().to_sec()
    third.handle.cancel()
    third.wait(10.0)
    ok = report(third, "PREEMPTED") and ok
    stopped_time = cancel_time
    if third.result is not None:
        p = third.result.stopped_at.position
        print("goal 3 stopped at (%.3f, %.3f, %.3f) m" % (p.x, p.y, p.z))
    if recorder is not None:
        rospy.sleep(1.0)  # the stop (the cancel answers at once, the frame comes to rest after it)
        recorder.sub.unregister()
        with recorder.lock:
            samples = list(recorder.samples)
        if len(samples) < 10:
            fail("only %d messages on ~command: is --command-topic right?" % len(samples), 1)
        if third.result is not None:
            # The rest instant: the first command at the stop pose.
            s = third.result.stopped_at.position
            for c in samples:
                if c[0] > cancel_time and math.dist(c[1:], (s.x, s.y, s.z)) < 1e-6:
                    stopped_time = c[0]
                    break
        plot(args.plot, samples, first, second, third, cancel_time, stopped_time)
    if not ok:
        fail("a goal did not end as expected (above)", 1)
    print("all three goals ended as expected")


if __name__ == "__main__":
    main()
