#!/usr/bin/python3
"""Draw a request with `blend_radius` against the same request with sharp corners (blend_radius 0),
both run through se3_interpolate: the paths of the body origin with the blend zones (circles of
radius r_i = min(blend_radius, half of each adjacent leg's chord length) about the interior
waypoints), and the speed against time.

usage: plot_corner_blend.py SE3_INTERPOLATE REQUEST.yaml OUT.png
(e.g. plot_corner_blend.py $SE3_WS/devel/lib/se3_interpolation/se3_interpolate
      docs/examples/corner_blend.yaml docs/corner_blend.png)
"""
import csv
import io
import math
import os
import subprocess
import sys
import tempfile

import matplotlib
import yaml

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def run(cli, request):
    with tempfile.NamedTemporaryFile("w", suffix=".yaml", delete=False) as f:
        yaml.safe_dump(request, f)
        path = f.name
    try:
        out = subprocess.run([cli, path], check=True, capture_output=True, text=True)
    finally:
        os.unlink(path)
    figures = dict(line.split(": ", 1) for line in out.stderr.splitlines() if ": " in line)
    return [{k: float(v) for k, v in r.items()} for r in csv.DictReader(io.StringIO(out.stdout))], figures


def chord(a, b, rho):
    """sqrt(|dp|^2 + (rho dtheta)^2) between two waypoints of the request."""
    dp = math.dist(a["position"], b["position"])
    qa, qb = a["orientation"], b["orientation"]
    dot = abs(sum(x * y for x, y in zip(qa, qb))) / math.sqrt(sum(x * x for x in qa) * sum(x * x for x in qb))
    theta = 2.0 * math.acos(min(1.0, dot))
    return math.hypot(dp, rho * theta)


def main(argv):
    if len(argv) != 3:
        print(__doc__, file=sys.stderr)
        return 2
    cli, request_path, out_path = argv
    with open(request_path) as f:
        request = yaml.safe_load(f)
    radius = float(request["blend_radius"])
    rho = float(request.get("rotation_scale", 0.0)) or 1.0
    blended, blended_figures = run(cli, request)
    sharp, sharp_figures = run(cli, dict(request, blend_radius=0.0))

    w = request["waypoints"]
    fig, (ax_path, ax_speed) = plt.subplots(1, 2, figsize=(12, 4.6), gridspec_kw={"width_ratios": [1.15, 1]})
    ax_path.plot([r["x"] for r in sharp], [r["y"] for r in sharp], "--", color="0.45", lw=1.5,
                 label="blend_radius 0 (sharp corners)")
    ax_path.plot([r["x"] for r in blended], [r["y"] for r in blended], "-", color="tab:blue", lw=2.2,
                 label="blend_radius %g m" % radius)
    for i in range(1, len(w) - 1):
        r_i = min(radius, chord(w[i - 1], w[i], rho) / 2.0, chord(w[i], w[i + 1], rho) / 2.0)
        ax_path.add_patch(plt.Circle(w[i]["position"][:2], r_i, color="tab:green", alpha=0.18, lw=0))
    ax_path.plot([p["position"][0] for p in w], [p["position"][1] for p in w], "o", color="goldenrod", ms=6,
                 label="waypoints")
    ax_path.set_aspect("equal")
    ax_path.set_xlabel("x [m]")
    ax_path.set_ylabel("y [m]")
    ax_path.set_title("path of the body origin; blend zones (r_i) in green")
    ax_path.legend(loc="upper left", fontsize=9)

    def speed(rows):
        return [math.sqrt(r["vx"] ** 2 + r["vy"] ** 2 + r["vz"] ** 2) for r in rows]

    timing = request.get("timing", "stretch")
    ax_speed.plot([r["t"] for r in sharp], speed(sharp), "--", color="0.45", lw=1.5,
                  label="sharp: %.2f s" % float(sharp_figures["duration"]))
    ax_speed.plot([r["t"] for r in blended], speed(blended), "-", color="tab:blue", lw=2.2,
                  label="blended: %.2f s" % float(blended_figures["duration"]))
    ax_speed.set_xlabel("t [s]")
    ax_speed.set_ylabel("|dp/dt| [m/s]")
    ax_speed.set_title("linear speed, timing: %s" % timing)
    ax_speed.set_ylim(0.0, 1.25 * max(speed(blended) + speed(sharp)))
    ax_speed.legend(loc="upper center", ncol=2, fontsize=9)
    fig.tight_layout()
    fig.savefig(out_path, dpi=80)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
