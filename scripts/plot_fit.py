#!/usr/bin/python3
"""Plot a recording against the curve fit through it (se3_interpolate's CSVs) into a PNG.

usage: plot_fit.py RECORDING.csv FITTED.csv OUT.png [--request REQUEST.yaml [--cli SE3_INTERPOLATE]]
                   [--figures FIGURES.txt] [--title TITLE]

RECORDING.csv has the columns t,x,y,z,qx,qy,qz,qw (found by name, others ignored: what
`se3_interpolate --waypoints` reads); FITTED.csv is se3_interpolate's output for the fit request
(t,x,y,z,qx,qy,qz,qw,...). Three panels against time t [s], the recording as light dots and the fit
as lines: position x, y, z [m]; the rotation vector [rad] of R(t) (world frame; quaternion signs
do not matter, and it continues past pi instead of jumping); and the residuals of each recorded
pose from the fit at its time: position distance [mm] and rotation angle [deg] (log scale, so
that noise and outliers both show).

The residuals are exact: they need the fitted curve at the recording's times. If FITTED.csv has a
sample at every recording time (to 1e-9 s: sample_period a divisor of the recording's period, or
sample_times equal to its times) those samples are used; otherwise --request REQUEST.yaml runs
the fit again through the CLI (--cli, default `rosrun se3_interpolation se3_interpolate`, with
--waypoints RECORDING.csv) with sample_times set to the recording's times.

--figures takes the CLI's standard error of the fit (`2>FIGURES.txt`): residual_linear,
residual_angular and control_poses go into the title.

Runs with Debian's /usr/bin/python3 (the shebang): run it as scripts/plot_fit.py; a `python3`
from pyenv or a virtualenv may lack matplotlib.
"""
import argparse
import importlib.util
import math
import os
import subprocess
import sys
import tempfile

try:
    import matplotlib
    import yaml
except ImportError as e:
    sys.exit("plot_fit: error: %s: %s; run the script as scripts/plot_fit.py (its shebang is Debian's "
             "/usr/bin/python3, with python3-matplotlib and python3-yaml)" % (sys.executable, e))

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

# The CSV reader, the figures' reader and the rotation vectors with their branches are
# plot_trajectory.py's (installed beside this script).
_spec = importlib.util.spec_from_file_location(
    "plot_trajectory", os.path.join(os.path.dirname(os.path.abspath(__file__)), "plot_trajectory.py"))
plot_trajectory = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(plot_trajectory)

POSE = ["t", "x", "y", "z", "qx", "qy", "qz", "qw"]
COLOURS = ["tab:red", "tab:green", "tab:blue"]


def read_poses(path):
    """The columns t,x,y,z,qx,qy,qz,qw of a CSV, by name, as lists of floats."""
    with open(path, newline="") as f:
        return plot_trajectory.read_columns(f, path, POSE, "t,x,y,z,qx,qy,qz,qw")


def quaternions(d):
    return list(zip(d["qx"], d["qy"], d["qz"], d["qw"]))


def angle_between(a, b):
    """Rotation angle (rad, in [0, pi]) of a^-1 b for unit quaternions a, b of either sign:
    2 atan2(|vec(a^-1 b)|, |w(a^-1 b)|), precise near 0 (unlike acos)."""
    ax, ay, az, aw = a
    bx, by, bz, bw = b
    # a^-1 b with a^-1 = (-ax, -ay, -az, aw)
    x = aw * bx - ax * bw - ay * bz + az * by
    y = aw * by + ax * bz - ay * bw - az * bx
    z = aw * bz - ax * by + ay * bx - az * bw
    w = aw * bw + ax * bx + ay * by + az * bz
    return 2 * math.atan2(math.sqrt(x * x + y * y + z * z), abs(w))


def samples_at(fitted, times, tolerance=1e-9):
    """Indices of FITTED's samples at `times` (each within tolerance), or None if one is missing."""
    out = []
    j = 0
    ft = fitted["t"]
    for t in times:
        while j < len(ft) and ft[j] < t - tolerance:
            j += 1
        if j == len(ft) or abs(ft[j] - t) > tolerance:
            return None
        out.append(j)
    return out


def fit_at_recording(cli, request, recording_path, times):
    """The fit of REQUEST through the recording, sampled by the CLI at the recording's times."""
    with open(request) as f:
        req = yaml.safe_load(f) or {}
    for k in ("sample_period", "sample_count"):
        req.pop(k, None)
    req["sample_times"] = list(times)
    with tempfile.NamedTemporaryFile("w", suffix=".yaml", delete=False) as f:
        yaml.safe_dump(req, f)
        path = f.name
    out = path[:-5] + ".csv"
    try:
        subprocess.run(cli + [path, "--waypoints", recording_path, "-o", out], check=True,
                       stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, universal_newlines=True)
        return read_poses(out)
    except subprocess.CalledProcessError as e:
        raise RuntimeError("%s failed (%d): %s" % (" ".join(cli), e.returncode, e.stderr.strip()))
    finally:
        os.unlink(path)
        if os.path.exists(out):
            os.unlink(out)


def residuals(recording, at):
    """Position distance (m) and rotation angle (rad) of each recorded pose from `at`, the fit
    sampled at the recording's times."""
    lin = [math.dist((recording["x"][i], recording["y"][i], recording["z"][i]),
                     (at["x"][i], at["y"][i], at["z"][i])) for i in range(len(recording["t"]))]
    ang = [angle_between(a, b) for a, b in zip(quaternions(at), quaternions(recording))]
    return lin, ang


def main(argv):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("recording", help="the recorded poses, CSV t,x,y,z,qx,qy,qz,qw")
    parser.add_argument("fitted", help="se3_interpolate's CSV of the fit")
    parser.add_argument("png", help="output PNG")
    parser.add_argument("--request", metavar="REQUEST.yaml",
                        help="the fit's request file, to sample the fit at the recording's times")
    parser.add_argument("--cli", metavar="SE3_INTERPOLATE",
                        help="the CLI binary (default: rosrun se3_interpolation se3_interpolate)")
    parser.add_argument("--figures", metavar="FILE", help="se3_interpolate's standard error of the fit")
    parser.add_argument("--title", default="")
    args = parser.parse_args(argv)
    try:
        rec = read_poses(args.recording)
        fit = read_poses(args.fitted)
        idx = samples_at(fit, rec["t"])
        if idx is not None:
            at = {c: [fit[c][j] for j in idx] for c in POSE}
        elif args.request:
            cli = [args.cli] if args.cli else ["rosrun", "se3_interpolation", "se3_interpolate"]
            at = fit_at_recording(cli, args.request, args.recording, rec["t"])
            if len(at["t"]) != len(rec["t"]):
                raise RuntimeError("the CLI returned %d samples for %d recording times" % (len(at["t"]), len(rec["t"])))
        else:
            raise ValueError("%s has no sample at some recording times: sample the fit at them (sample_period a "
                             "divisor of the recording's period) or give --request REQUEST.yaml" % args.fitted)
        figures = plot_trajectory.read_figures(args.figures) if args.figures else {}
    except (OSError, ValueError, RuntimeError) as e:
        sys.exit("plot_fit: error: %s" % e)

    lin, ang = residuals(rec, at)
    rotation_vector = plot_trajectory.rotation_vector
    rv_fit = plot_trajectory.unwrap([rotation_vector(q) for q in quaternions(fit)])
    rv_at = plot_trajectory.unwrap([rotation_vector(q) for q in quaternions(at)])
    rv_rec = [plot_trajectory.nearest_branch(rotation_vector(q), ref) for q, ref in zip(quaternions(rec), rv_at)]

    fig, axes = plt.subplots(3, 1, figsize=(12, 10), sharex=True,
                             gridspec_kw={"height_ratios": [1, 1, 0.9]})
    dot = dict(s=6, alpha=0.35, linewidths=0)
    for k, c in enumerate("xyz"):
        axes[0].scatter(rec["t"], rec[c], color=COLOURS[k], label="recorded " + c, **dot)
        axes[0].plot(fit["t"], fit[c], color=COLOURS[k], lw=1.4, label="fit " + c)
        axes[1].scatter(rec["t"], [r[k] for r in rv_rec], color=COLOURS[k], label="recorded r" + c, **dot)
        axes[1].plot(fit["t"], [r[k] for r in rv_fit], color=COLOURS[k], lw=1.4, label="fit r" + c)
    axes[0].set_ylabel("position [m]")
    axes[0].set_title("position")
    axes[1].set_ylabel("rotation vector [rad]")
    axes[1].set_title("rotation (rotation vector of R(t), world frame)")
    for a in axes[:2]:
        a.legend(fontsize=8, loc="center left", bbox_to_anchor=(1.01, 0.5), markerscale=2)
        a.grid(alpha=0.3)
    floor = 1e-4
    axes[2].scatter(rec["t"], [max(floor, 1000 * d) for d in lin], s=8, color="tab:purple",
                    label="position distance [mm]")
    axes[2].scatter(rec["t"], [max(floor, math.degrees(a)) for a in ang], s=8, color="tab:orange",
                    marker="x", linewidths=0.8, label="rotation angle [deg]")
    axes[2].set_yscale("log")
    axes[2].set_ylabel("residual [mm] / [deg]")
    axes[2].set_title("residuals: each recorded pose from the fit at its time")
    axes[2].legend(fontsize=8, loc="center left", bbox_to_anchor=(1.01, 0.5), markerscale=1.5)
    axes[2].grid(alpha=0.3, which="both")
    axes[2].set_xlabel("t [s]")
    title = args.title or "curve fit of %s (%d poses)" % (os.path.basename(args.recording), len(rec["t"]))
    parts = []
    if "residual_linear" in figures:
        parts.append("residual_linear %.2f mm" % (1000 * figures["residual_linear"]))
    if "residual_angular" in figures:
        parts.append("residual_angular %.3f deg" % math.degrees(figures["residual_angular"]))
    if "control_poses" in figures:
        parts.append("control_poses %d" % figures["control_poses"])
    fig.suptitle(title + ("\n" + ", ".join(parts) + " (RMS over the recording)" if parts else ""))
    fig.tight_layout()
    fig.savefig(args.png, dpi=100)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
