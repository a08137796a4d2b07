#!/usr/bin/python3
"""Draw docs/replan.png: a motion replaced mid-way by a new one that starts in its current state.

usage: plot_replan.py [SE3_INTERPOLATE] [OUT.png]

Runs the CLI (default: se3_interpolate on PATH) twice: the old motion, sampled at the switch time
T_s = 1.2 s among others, then the new request with start_state = the old motion's pose, velocity
and acceleration at T_s (what the node does for `from_current`), and plots both against the same
clock: the path in the x-y plane, and x, |v| and the acceleration's y component against time, the switch marked. Pose space
only; needs Debian's python3-matplotlib (the shebang).
"""
import csv
import io
import math
import os
import subprocess
import sys
import tempfile

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

T_SWITCH = 1.2
OLD = """waypoints:
  - {position: [0, 0, 0], orientation: [0, 0, 0, 1]}
  - {position: [1, 0.8, 0], orientation: [0, 0, 0.3826834, 0.9238795]}
  - {position: [2, 0, 0], orientation: [0, 0, 0.7071068, 0.7071068]}
  - {position: [3, 0.8, 0], orientation: [0, 0, 0, 1]}
times: [0, 1, 2, 3]
sample_period: 0.01
"""
NEW = """start_state:
  pose: {{position: [{p}], orientation: [{q}]}}
  velocity: {{linear: [{v}], angular: [{w}]}}
  acceleration: {{linear: [{a}], angular: [{al}]}}
waypoints:
  - {{position: [2.3, 0.6, 0], orientation: [0, 0, 0.7071068, 0.7071068]}}
  - {{position: [2.6, 1.8, 0], orientation: [0, 0, 1, 0]}}
times: [1.2, 2.2]
sample_period: 0.01
"""


def run(cli, text):
    with tempfile.NamedTemporaryFile("w", suffix=".yaml", delete=False) as f:
        f.write(text)
    try:
        out = subprocess.run([cli, f.name], check=True, capture_output=True, text=True).stdout
    finally:
        os.unlink(f.name)
    rows = list(csv.reader(io.StringIO(out)))
    return [[float(x) for x in r] for r in rows[1:]]


def main():
    cli = sys.argv[1] if len(sys.argv) > 1 else "se3_interpolate"
    out = sys.argv[2] if len(sys.argv) > 2 else os.path.join(os.path.dirname(__file__), "..", "docs", "replan.png")
    old = run(cli, OLD)
    state = min(old, key=lambda r: abs(r[0] - T_SWITCH))
    fmt = lambda xs: ", ".join(repr(x) for x in xs)  # noqa: E731
    new = run(cli, NEW.format(p=fmt(state[1:4]), q=fmt(state[4:8]), v=fmt(state[8:11]), w=fmt(state[11:14]),
                              a=fmt(state[14:17]), al=fmt(state[17:20])))
    t_switch = state[0]
    norm = lambda r, i: math.sqrt(r[i] ** 2 + r[i + 1] ** 2 + r[i + 2] ** 2)  # noqa: E731

    fig, axes = plt.subplots(1, 4, figsize=(16, 3.8))
    before = [r for r in old if r[0] <= t_switch]
    after = [r for r in old if r[0] >= t_switch]
    ax = axes[0]
    ax.plot([r[1] for r in before], [r[2] for r in before], "C0", label="old motion")
    ax.plot([r[1] for r in after], [r[2] for r in after], "C0:", label="old motion (replaced)")
    ax.plot([r[1] for r in new], [r[2] for r in new], "C1", label="new motion (start_state / from_current)")
    ax.plot([state[1]], [state[2]], "ko", label="switch T_s = %.1f s" % t_switch)
    ax.set_xlabel("x [m]")
    ax.set_ylabel("y [m]")
    ax.set_aspect("equal")
    ax.set_title("path (x-y)")
    ax.legend(fontsize=7, loc="upper left")
    panels = [("x [m]", lambda r: r[1]), ("|v| [m/s]", lambda r: norm(r, 8)),
              ("acceleration a_y [m/s^2]", lambda r: r[15])]
    for ax, (label, f) in zip(axes[1:], panels):
        ax.plot([r[0] for r in before], [f(r) for r in before], "C0")
        ax.plot([r[0] for r in after], [f(r) for r in after], "C0:")
        ax.plot([t_switch + r[0] for r in new], [f(r) for r in new], "C1")
        ax.axvline(t_switch, color="k", lw=0.8, ls="--")
        ax.set_xlabel("t [s]")
        ax.set_title(label)
    fig.suptitle("Replanning: the new motion starts in the old one's pose, velocity and acceleration at T_s "
                 "(C2 switch), then goes through its waypoints", fontsize=10)
    fig.tight_layout()
    fig.savefig(out, dpi=90)
    print("wrote", out)


if __name__ == "__main__":
    main()
