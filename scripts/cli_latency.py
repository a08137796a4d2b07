#!/usr/bin/python3
"""Wall time of se3_interpolate on the request of scripts/service_latency.sh.

Writes the request file (N waypoints on the walk of bench/service_latency.cpp, `interpolating`,
double_geodesic, M samples) to a temporary folder and runs the CLI on it R times each way: the CSV
to stdout (into a file of the same folder), and with `-o OUT.csv` (written atomically: a
temporary file, fsync, rename). Prints the median and minimum wall time, the CPU time (user +
system) and the CSV's size. bench/bench_cli_output.cpp times the planner and the formatting apart.
scripts/service_latency.sh runs it after the service clients.

Usage: cli_latency.py CLI [--waypoints N] [--samples M] [--repetitions R]
       (CLI: the se3_interpolate binary, e.g. $SE3_WS/devel/lib/se3_interpolation/se3_interpolate)
"""
import argparse
import math
import os
import resource
import subprocess
import tempfile
import time


def waypoint(i):
    """Waypoint i of bench/service_latency.cpp as YAML (q = q_z(yaw) q_x(roll), orientation x, y, z, w)."""
    yaw, roll = 0.4 * i, 0.3 * math.sin(0.7 * i)
    cy, sy, cr, sr = math.cos(0.5 * yaw), math.sin(0.5 * yaw), math.cos(0.5 * roll), math.sin(0.5 * roll)
    position = (0.3 * i, math.sin(0.5 * i), 0.2 * math.cos(0.3 * i))
    orientation = (cy * sr, sy * sr, sy * cr, cy * cr)
    return "  - {position: [%s], orientation: [%s]}\n" % (", ".join(map(repr, position)),
                                                        ", ".join(map(repr, orientation)))


def children_cpu():
    usage = resource.getrusage(resource.RUSAGE_CHILDREN)
    return usage.ru_utime + usage.ru_stime


def timed(command, stdout):
    """Runs command; returns (wall s, CPU s)."""
    cpu = children_cpu()
    start = time.monotonic()
    subprocess.run(command, stdout=stdout, stderr=subprocess.DEVNULL, check=True)
    return time.monotonic() - start, children_cpu() - cpu


def report(name, runs, csv_bytes):
    walls = sorted(w for w, _ in runs)
    cpus = sorted(c for _, c in runs)
    print("  %s: wall median %.3f s, min %.3f s; CPU median %.3f s; CSV %.1f MB; %d runs" %
          (name, walls[len(walls) // 2], walls[0], cpus[len(cpus) // 2], csv_bytes / 1e6, len(runs)))


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("cli")
    parser.add_argument("--waypoints", type=int, default=1000)
    parser.add_argument("--samples", type=int, default=100000)
    parser.add_argument("--repetitions", type=int, default=3)
    args = parser.parse_args()

    with tempfile.TemporaryDirectory(prefix="se3_cli_latency.") as work:
        request = os.path.join(work, "request.yaml")
        with open(request, "w") as f:
            f.write("waypoints:\n")
            f.writelines(waypoint(i) for i in range(args.waypoints))
            f.write("curve: interpolating\ngeometry: double_geodesic\nsample_count: %d\n" % args.samples)
        stdout_csv = os.path.join(work, "stdout.csv")
        out_csv = os.path.join(work, "out.csv")
        to_stdout, to_file = [], []
        for _ in range(max(1, args.repetitions)):
            with open(stdout_csv, "wb") as f:
                to_stdout.append(timed([args.cli, request], f))
            to_file.append(timed([args.cli, request, "-o", out_csv], subprocess.DEVNULL))
        print("se3_interpolate: %d waypoints, %d samples (%s)" % (args.waypoints, args.samples, args.cli))
        report("CSV to stdout (a file)", to_stdout, os.path.getsize(stdout_csv))
        report("-o OUT.csv (atomic, fsync)", to_file, os.path.getsize(out_csv))


if __name__ == "__main__":
    main()
