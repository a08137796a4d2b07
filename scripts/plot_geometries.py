#!/usr/bin/python3
"""Draw the same pair of poses joined under the two geometries (CSV files from se3_interpolate),
showing the path of the body origin and the body axes at every sample.

usage: plot_geometries.py SCREW.csv DOUBLE_GEODESIC.csv OUT.png
"""
import csv
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def read(path):
    with open(path) as f:
        return [{k: float(v) for k, v in r.items()} for r in csv.DictReader(f)]


def rotation_matrix(r):
    x, y, z, w = r["qx"], r["qy"], r["qz"], r["qw"]
    return [[1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
            [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
            [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)]]


def draw(ax, rows, title):
    ax.plot([r["x"] for r in rows], [r["y"] for r in rows], [r["z"] for r in rows], "k-", lw=1.5)
    for r in rows:
        m = rotation_matrix(r)
        for axis, color in enumerate("rgb"):
            ax.plot([r["x"], r["x"] + 0.25 * m[0][axis]], [r["y"], r["y"] + 0.25 * m[1][axis]],
                    [r["z"], r["z"] + 0.25 * m[2][axis]], color=color, lw=1.2)
    ax.set_title(title)
    ax.set_xlabel("x [m]")
    ax.set_ylabel("y [m]")
    ax.set_zlabel("z [m]")
    ax.set_xlim(-0.3, 1.8)
    ax.set_ylim(-0.5, 1.6)
    ax.set_zlim(-0.3, 1.0)
    ax.view_init(elev=35, azim=-60)


def main(argv):
    if len(argv) != 3:
        print(__doc__, file=sys.stderr)
        return 2
    fig = plt.figure(figsize=(11, 5))
    draw(fig.add_subplot(1, 2, 1, projection="3d"), read(argv[0]), "screw: the origin follows a helix")
    draw(fig.add_subplot(1, 2, 2, projection="3d"), read(argv[1]), "double_geodesic: the origin moves straight")
    fig.tight_layout()
    fig.savefig(argv[2], dpi=80)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
