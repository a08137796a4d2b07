"""SO(3)/SE(3) exp and log and the geodesic step in both geometries."""

import numpy as np
import pytest

import se3_interpolation as s

A = np.array([0.1, -0.2, 0.3, 0.0, 0.0, 0.0, 1.0])
B = np.array([1.0, 0.5, -0.4, 0.0, 0.38268343236508984, 0.0, 0.9238795325112867])


def random_rotation_vectors(n, rng, max_angle=np.pi - 1e-3):
    axes = rng.normal(size=(n, 3))
    axes /= np.linalg.norm(axes, axis=1)[:, None]
    return axes * rng.uniform(0, max_angle, size=(n, 1))


def test_so3_log_inverts_exp_from_tiny_to_near_half_turn_angles():
    rng = np.random.default_rng(1)
    omega = np.vstack([random_rotation_vectors(200, rng), [[1e-12, 0, 0], [0, 0, np.pi - 1e-9]]])
    q = s.so3_exp(omega)
    assert q.shape == (202, 4)
    np.testing.assert_allclose(np.linalg.norm(q, axis=1), 1.0, rtol=1e-15)
    back = s.so3_log(q)
    np.testing.assert_allclose(back, omega, rtol=1e-9, atol=1e-15)
    assert s.so3_log(q[-2])[0] == pytest.approx(1e-12, rel=1e-12)


def test_so3_log_of_q_and_minus_q_agree():
    q = s.so3_exp([0.3, -1.0, 2.0])
    assert np.array_equal(s.so3_log(q), s.so3_log(-q))


def test_se3_log_inverts_exp():
    rng = np.random.default_rng(2)
    xi = np.hstack([random_rotation_vectors(100, rng), rng.normal(size=(100, 3))])
    poses = s.se3_exp(xi)
    assert poses.shape == (100, 7)
    np.testing.assert_allclose(s.se3_log(poses), xi, rtol=1e-9, atol=1e-12)


def test_se3_exp_of_a_pure_translation_and_a_pure_rotation():
    np.testing.assert_array_equal(s.se3_exp([0, 0, 0, 1, 2, 3]), [1, 2, 3, 0, 0, 0, 1])
    np.testing.assert_allclose(s.se3_exp([0, 0, np.pi / 2, 0, 0, 0])[3:], s.so3_exp([0, 0, np.pi / 2]))


@pytest.mark.parametrize("geometry", ["double_geodesic", "screw"])
def test_the_geodesic_step_ends_at_its_points(geometry):
    ends = s.geodesic(A, B, [0.0, 1.0], geometry=geometry)
    np.testing.assert_allclose(ends[0], A, atol=1e-15)
    np.testing.assert_allclose(ends[1], B, atol=1e-15)


def test_the_double_geodesic_moves_the_position_on_a_line_and_the_screw_does_not():
    lam = np.linspace(-0.5, 1.5, 9)
    line = s.geodesic(A, B, lam)
    np.testing.assert_allclose(line[:, :3], A[:3] + lam[:, None] * (B[:3] - A[:3]), atol=1e-15)
    screw = s.geodesic(A, B, lam, geometry="screw")
    np.testing.assert_allclose(screw[:, 3:], line[:, 3:], atol=1e-15)  # same rotation path
    assert np.abs(screw[:, :3] - line[:, :3]).max() > 1e-3


def test_the_screw_step_is_a_exp_lam_log():
    # a⁻¹ b for a identity rotation at position p_a: (q_b, p_b − p_a); the step is a · Exp(λ ξ).
    xi = s.se3_log(np.hstack([B[:3] - A[:3], B[3:]]))
    half = s.se3_exp(0.5 * xi)
    np.testing.assert_allclose(s.geodesic(A, B, 0.5, geometry="screw"), half + np.r_[A[:3], 0, 0, 0, 0], atol=1e-15)


def test_errors():
    with pytest.raises(s.NonUniqueGeodesicError, match="^a and b: "):
        s.geodesic(A, [0, 0, 0, 1, 0, 0, 0], 0.5)
    with pytest.raises(s.InvalidInputError, match=r"^q: expected shape \(4,\) or \(N, 4\), got \(2, 3\)"):
        s.so3_log(np.zeros((2, 3)))
    with pytest.raises(s.InvalidInputError, match=r"^q\[1\]: quaternion norm"):
        s.so3_log([[0, 0, 0, 1], [0, 0, 0, 2]])
    with pytest.raises(s.InvalidInputError, match="^geometry: unknown value 'round'"):
        s.geodesic(A, B, 0.5, geometry="round")
    with pytest.raises(TypeError, match="^xi: expected numbers"):
        s.se3_exp("twist")
