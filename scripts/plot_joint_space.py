#!/usr/bin/python3
"""Draw docs/joint_space.png: the UR5e of config/robots/ following docs/examples/ur5e_joint_space.yaml
under the Cartesian bounds alone and under the Cartesian bounds and its joint limits at once.

usage: plot_joint_space.py [SE3_INTERPOLATE] [OUT.png]

Runs the CLI (default: se3_interpolate on PATH) twice from the repository's root: with the
joint limits of config/robots/ur5e_joint_limits.yaml scaled by 100 (so that only the Cartesian
bounds act) and with the file's own. Plots, against time, each run's joint velocities and
accelerations with the limits dashed, and the tool's linear speed with its bound. Needs Debian's
python3-matplotlib (the shebang).
"""
import csv
import io
import os
import subprocess
import sys
import tempfile

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
REQUEST = os.path.join(ROOT, "docs", "examples", "ur5e_joint_space.yaml")
URDF = os.path.join(ROOT, "config", "robots", "ur5e.urdf")
LIMITS = os.path.join(ROOT, "config", "robots", "ur5e_joint_limits.yaml")
JOINTS = ["shoulder_pan_joint", "shoulder_lift_joint", "elbow_joint", "wrist_1_joint", "wrist_2_joint",
          "wrist_3_joint"]
MAX_LINEAR_VELOCITY = 1.0  # the request's max_linear_velocity (docs/examples/ur5e_joint_space.yaml)


def limits(scale):
    """The limits file's text with every velocity and acceleration scaled by `scale`, and the file's values."""
    lines, velocity, acceleration = [], {}, {}
    joint = None
    with open(LIMITS) as f:
        for line in f:
            stripped = line.strip()
            if stripped.endswith(":") and not stripped.startswith("#") and stripped != "joint_limits:":
                joint = stripped[:-1]
            for key, table in (("max_velocity:", velocity), ("max_acceleration:", acceleration)):
                if stripped.startswith(key):
                    value = float(stripped.split(":")[1])
                    table[joint] = value
                    line = line.replace(stripped, "%s %r" % (key, value * scale))
            lines.append(line)
    return "".join(lines), velocity, acceleration


def run(cli, limits_path):
    out = subprocess.run([cli, REQUEST, "--urdf", URDF, "--base-link", "base_link", "--tip-link", "tool0",
                          "--joint-limits", limits_path], check=True, capture_output=True, text=True)
    rows = list(csv.DictReader(io.StringIO(out.stdout)))
    return {k: [float(r[k]) for r in rows] for k in rows[0]}


def panel(axes, data, title, velocity, acceleration):
    t = data["t"]
    for i, j in enumerate(JOINTS):
        color = "C%d" % i
        axes[0].plot(t, data["dq_" + j], color=color, label=j)
        axes[1].plot(t, data["ddq_" + j], color=color)
    for row, table in ((0, velocity), (1, acceleration)):
        for value in set(table.values()):
            for sign in (1, -1):
                axes[row].axhline(sign * value, color="k", linestyle="--", linewidth=0.8)
    speed = [(vx * vx + vy * vy + vz * vz) ** 0.5 for vx, vy, vz in zip(data["vx"], data["vy"], data["vz"])]
    axes[2].plot(t, speed, color="C0")
    axes[2].axhline(MAX_LINEAR_VELOCITY, color="k", linestyle="--", linewidth=0.8)
    axes[0].set_title("%s: %.2f s" % (title, t[-1] - t[0]))
    axes[0].set_ylabel("joint velocity (rad/s)")
    axes[1].set_ylabel("joint acceleration (rad/s²)")
    axes[2].set_ylabel("tool speed (m/s)")
    axes[2].set_xlabel("t (s)")


def main(argv):
    cli = argv[1] if len(argv) > 1 else "se3_interpolate"
    out = argv[2] if len(argv) > 2 else os.path.join(ROOT, "docs", "joint_space.png")
    loose_text, velocity, acceleration = limits(100.0)
    with tempfile.TemporaryDirectory() as folder:
        loose = os.path.join(folder, "loose_limits.yaml")
        with open(loose, "w") as f:
            f.write(loose_text)
        cartesian = run(cli, loose)
        joint = run(cli, LIMITS)
    fig, axes = plt.subplots(3, 2, figsize=(12, 9), sharex="col")
    panel(axes[:, 0], cartesian, "Cartesian bounds only", velocity, acceleration)
    panel(axes[:, 1], joint, "Cartesian bounds and joint limits", velocity, acceleration)
    axes[0, 0].legend(fontsize=7, loc="upper right")
    fig.suptitle("UR5e following docs/examples/ur5e_joint_space.yaml (time_optimal); dashed: limits and bound")
    fig.tight_layout()
    fig.savefig(out, dpi=90)
    print("wrote %s" % out)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
