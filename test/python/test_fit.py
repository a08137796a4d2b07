"""The fit of a noisy recording: a known motion, sampled, with noise on positions and rotations,
fitted by curve fit (generate and the fit() curve builder)."""

import numpy as np

import se3_interpolation as s
from conftest import WAYPOINTS

NOISE = 0.002  # m per position component, rad per rotation-vector component


def recording():
    """The true motion's poses at 400 times over 4 s, and the same with noise."""
    truth = s.interpolating(WAYPOINTS, times=[0, 1.5, 2.5, 4.0])
    t = np.linspace(0.0, 4.0, 400)
    pose = truth.evaluate(t).pose
    rng = np.random.default_rng(7)
    noisy = pose.copy()
    noisy[:, :3] += rng.normal(0, NOISE, (len(t), 3))
    # The rotation noise as a small rotation applied in the body frame: q ⊗ Exp(n).
    dq = s.so3_exp(rng.normal(0, NOISE, (len(t), 3)))
    x1, y1, z1, w1 = pose[:, 3:].T
    x2, y2, z2, w2 = dq.T
    noisy[:, 3:] = np.stack([w1 * x2 + x1 * w2 + y1 * z2 - z1 * y2, w1 * y2 - x1 * z2 + y1 * w2 + z1 * x2,
                             w1 * z2 + x1 * y2 - y1 * x2 + z1 * w2, w1 * w2 - x1 * x2 - y1 * y2 - z1 * z2], axis=1)
    return t, pose, noisy


def test_the_fit_recovers_the_motion_within_the_noise():
    t, truth, noisy = recording()
    fitted = s.generate(curve="fit", waypoints=noisy, times=t, control_period=0.25, sample_times=t)
    # The residuals are the noise: √3 σ in RMS distance for three components.
    assert 0.7 * np.sqrt(3) * NOISE < fitted.residual_linear < 1.3 * np.sqrt(3) * NOISE
    assert 0.5 * np.sqrt(3) * NOISE < fitted.residual_angular < 1.5 * np.sqrt(3) * NOISE
    # ... and the fitted positions are much nearer the truth than the recording is.
    error = np.sqrt(np.mean(np.sum((fitted.pose[:, :3] - truth[:, :3]) ** 2, axis=1)))
    assert error < 0.4 * fitted.residual_linear
    assert len(fitted.knots) and fitted.control_poses.shape[1] == 7


def test_the_fit_curve_is_generates_fit():
    t, _, noisy = recording()
    curve = s.fit(noisy, times=t, control_period=0.25)
    fitted = s.generate(curve="fit", waypoints=noisy, times=t, control_period=0.25, sample_count=101)
    assert np.array_equal(curve.knots, fitted.knots)
    assert curve.residual_linear == fitted.residual_linear
    assert np.array_equal(curve.evaluate(fitted.t).pose, fitted.pose)
    # The fitted curve replays as a bspline of its control poses and knots (the CLI's --save-bspline).
    degree = len(fitted.knots) - len(fitted.control_poses) - 1
    replay = s.bspline(fitted.control_poses, knots=fitted.knots, degree=degree)
    np.testing.assert_allclose(replay.evaluate(fitted.t).pose, fitted.pose, atol=1e-12)
