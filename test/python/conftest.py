"""Shared fixtures of the Python module's tests: the built CLI, requests, and a runner of the CLI
on a request dict (scripts/run_python_tests.sh runs them against the workspace $SE3_WS)."""

import io
import os
import subprocess

import numpy as np
import pytest
import yaml

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
EXAMPLES = os.path.join(ROOT, "docs", "examples")

# Three poses, quarter turns about z with a lateral step: every family takes them.
WAYPOINTS = np.array(
    [
        [0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0],
        [1.0, 0.0, 0.2, 0.0, 0.0, 0.7071067811865476, 0.7071067811865476],
        [1.0, 1.0, 0.4, 0.0, 0.0, 1.0, 0.0],
        [0.3, 1.4, 0.1, 0.2705980500730985, 0.2705980500730985, 0.6532814824381882, 0.6532814824381883],
    ]
)


@pytest.fixture(scope="session")
def cli():
    """The se3_interpolate program of the workspace under test."""
    ws = os.environ.get("SE3_WS")
    assert ws, "SE3_WS is not set: source scripts/setup.bash first"
    path = os.path.join(ws, "devel", "lib", "se3_interpolation", "se3_interpolate")
    assert os.access(path, os.X_OK), f"{path} is not built"
    return path


class CliRun:
    """One run of the CLI: its exit status, its samples (M, 20) and its figures (name -> text)."""

    def __init__(self, completed):
        self.status = completed.returncode
        self.stderr = completed.stderr
        self.samples = None
        self.figures = {}
        if self.status == 0:
            self.samples = np.loadtxt(io.StringIO(completed.stdout), delimiter=",", skiprows=1, ndmin=2)
            for line in completed.stderr.splitlines():
                name, _, value = line.partition(": ")
                self.figures[name] = value

    @property
    def error(self):
        """The message after the CLI's `se3_interpolate: error: ` prefix."""
        prefix = "se3_interpolate: error: "
        assert self.stderr.startswith(prefix), self.stderr
        return self.stderr[len(prefix):].rstrip("\n")


@pytest.fixture
def run_cli(cli, tmp_path):
    """Runs the CLI on a request: a dict (written as YAML) or the path of a request file."""

    def run(request, *options):
        path = request
        if isinstance(request, dict):
            path = tmp_path / "request.yaml"
            path.write_text(yaml.safe_dump(request))
        return CliRun(subprocess.run([cli, str(path), *options], capture_output=True, text=True, timeout=120))

    return run


def as_yaml_request(request):
    """A request as the CLI reads it: numpy arrays as lists, waypoint rows [x, y, z, qx, qy, qz, qw]
    as {position: .., orientation: ..} (the CLI's spelling)."""
    out = {k: (v.tolist() if isinstance(v, np.ndarray) else v) for k, v in request.items()}
    if isinstance(out.get("waypoints"), list):
        out["waypoints"] = [
            {"position": list(w[:3]), "orientation": list(w[3:])} if isinstance(w, list) and len(w) == 7 else w
            for w in out["waypoints"]
        ]
    return out


def samples_of(trajectory):
    """generate()'s samples as the CLI's 20 columns."""
    return np.hstack([trajectory.t[:, None], trajectory.pose, trajectory.velocity, trajectory.acceleration])
