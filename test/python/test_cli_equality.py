"""The module's results equal the CLI's for the docs' example requests, bit for bit: the CLI writes
every number in its shortest round-trip form (src/cli/csv_writer.cpp), so its CSV parses back to
the same doubles; the figures it prints with 12 significant digits are compared at that precision."""

import glob
import os

import numpy as np
import pytest
import yaml

import se3_interpolation as s
from conftest import EXAMPLES, samples_of


def needs_an_arm(path):
    """Whether a docs example is an arm's (joint_seed): it runs with a URDF, which the module does not
    take; test/cli/test_cli.cpp checks its joint columns against the planner's."""
    with open(path) as f:
        return "joint_seed" in (yaml.safe_load(f) or {})


REQUESTS = [p for p in sorted(glob.glob(os.path.join(EXAMPLES, "*.yaml"))) if not needs_an_arm(p)]
RECORDING = os.path.join(EXAMPLES, "fit_recording.csv")


def example(path):
    """The request of a docs example and the CLI options it runs with (fit reads a recording)."""
    with open(path) as f:
        request = yaml.safe_load(f)
    if request.get("curve") != "fit":
        return request, []
    recording = np.loadtxt(RECORDING, delimiter=",", skiprows=1)
    request.update(times=recording[:, 0], waypoints=recording[:, 1:8])
    return request, ["--waypoints", RECORDING]


def test_the_examples_are_found():
    assert len(REQUESTS) >= 5


@pytest.mark.parametrize("path", REQUESTS, ids=os.path.basename)
def test_samples_equal_the_clis_bit_for_bit(path, run_cli):
    request, options = example(path)
    cli = run_cli(path, *options)
    assert cli.status == 0, cli.stderr
    mine = samples_of(s.generate(request))
    assert mine.shape == cli.samples.shape
    assert np.array_equal(mine, cli.samples), f"largest difference {np.abs(mine - cli.samples).max()}"


@pytest.mark.parametrize("path", REQUESTS, ids=os.path.basename)
def test_figures_equal_the_clis_at_its_precision(path, run_cli):
    request, options = example(path)
    cli = run_cli(path, *options)
    r = s.generate(request)
    figures = dict(r.figures)
    if len(r.control_poses) and len(r.knots):
        figures["control_poses"] = len(r.control_poses)
    printed = {k: v for k, v in cli.figures.items() if k not in ("waypoint_times", "frame_id", "time_origin")}
    assert {k: "%.12g" % v for k, v in figures.items()} == printed
    assert ", ".join("%.12g" % t for t in r.waypoint_times) == cli.figures["waypoint_times"]
