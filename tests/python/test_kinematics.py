"""Euler-angle kinematics: R, J, J^-1, J_dot and the pitch singularity."""

from __future__ import annotations

import numpy as np
import pytest

import neurov
import reference_model as ref

N_POINTS = 50


def random_angles(rng: np.random.Generator, max_pitch: float = np.pi) -> np.ndarray:
    return np.array(
        [rng.uniform(-np.pi, np.pi), rng.uniform(-max_pitch, max_pitch), rng.uniform(-np.pi, np.pi)]
    )


def test_rotation_is_a_proper_rotation(rng: np.random.Generator) -> None:
    for _ in range(N_POINTS):
        r = neurov.rotation(*random_angles(rng))
        assert r.shape == (3, 3)
        assert r.dtype == np.float64
        np.testing.assert_allclose(r.T @ r, np.eye(3), atol=1e-14)
        np.testing.assert_allclose(r @ r.T, np.eye(3), atol=1e-14)
        assert np.linalg.det(r) == pytest.approx(1.0, abs=1e-14)


def test_rotation_equals_rz_ry_rx(rng: np.random.Generator) -> None:
    for _ in range(N_POINTS):
        phi, theta, psi = random_angles(rng)
        np.testing.assert_allclose(
            neurov.rotation(phi, theta, psi), ref.rotation(phi, theta, psi), rtol=0, atol=1e-14
        )


@pytest.mark.parametrize(
    ("angles", "body_x_in_ned"),
    [
        ((0.0, 0.0, np.pi / 2), [0.0, 1.0, 0.0]),  # heading east
        ((0.0, np.pi / 2, 0.0), [0.0, 0.0, -1.0]),  # nose up: body x points up (z down)
        ((0.3, 0.0, 0.0), [1.0, 0.0, 0.0]),  # roll leaves the body x axis alone
    ],
)
def test_rotation_known_poses(angles: tuple[float, float, float], body_x_in_ned: list[float]) -> None:
    np.testing.assert_allclose(neurov.rotation(*angles) @ [1.0, 0.0, 0.0], body_x_in_ned, atol=1e-15)


@pytest.mark.parametrize("theta", [np.pi / 2, -np.pi / 2])
def test_rotation_is_orthonormal_at_the_singularity(theta: float) -> None:
    r = neurov.rotation(0.4, theta, -1.1)
    np.testing.assert_allclose(r.T @ r, np.eye(3), atol=1e-14)
    np.testing.assert_allclose(r, ref.rotation(0.4, theta, -1.1), atol=1e-15)


def test_jacobian_matches_reference(rng: np.random.Generator) -> None:
    for _ in range(N_POINTS):
        eta = ref.random_pose(rng)
        np.testing.assert_allclose(neurov.jacobian(eta), ref.jacobian(eta), rtol=1e-13, atol=1e-14)
        np.testing.assert_allclose(
            neurov.jacobian_inverse(eta), ref.jacobian_inverse(eta), rtol=1e-13, atol=1e-14
        )


def test_jacobian_is_block_diagonal_and_position_independent(rng: np.random.Generator) -> None:
    eta = ref.random_pose(rng)
    j = neurov.jacobian(eta)
    assert np.all(j[:3, 3:] == 0.0) and np.all(j[3:, :3] == 0.0)
    moved = eta.copy()
    moved[:3] += [100.0, -3.0, 7.0]
    np.testing.assert_array_equal(neurov.jacobian(moved), j)


def test_jacobian_inverse_inverts_jacobian(rng: np.random.Generator) -> None:
    for _ in range(N_POINTS):
        eta = ref.random_pose(rng, max_pitch=1.45)
        j = neurov.jacobian(eta)
        j_inv = neurov.jacobian_inverse(eta)
        np.testing.assert_allclose(j_inv @ j, np.eye(6), atol=1e-12)
        np.testing.assert_allclose(j @ j_inv, np.eye(6), atol=1e-12)


@pytest.mark.parametrize(
    "theta", [np.pi / 2, -np.pi / 2, 3 * np.pi / 2, np.pi / 2 + 2 * np.pi, np.pi / 2 + 1e-10]
)
def test_jacobian_and_jacobian_dot_refuse_the_singularity(theta: float) -> None:
    eta = np.array([1.0, 2.0, 3.0, 0.2, theta, -0.4])
    with pytest.raises(ValueError, match="'eta'") as err:
        neurov.jacobian(eta)
    assert "singularity" in str(err.value)
    with pytest.raises(ValueError, match="'eta'") as err:
        neurov.jacobian_dot(eta, np.full(6, 0.1))
    assert "singularity" in str(err.value)
    assert neurov.is_near_singularity(eta)


@pytest.mark.parametrize("theta", [np.pi / 2, -np.pi / 2])
def test_jacobian_inverse_is_defined_at_the_singularity(theta: float) -> None:
    eta = np.array([0.0, 0.0, 0.0, 0.3, theta, 0.5])
    j_inv = neurov.jacobian_inverse(eta)
    assert np.all(np.isfinite(j_inv))
    np.testing.assert_allclose(j_inv, ref.jacobian_inverse(eta), atol=1e-7)


@pytest.mark.parametrize("theta", [np.pi / 2, -np.pi / 2])
def test_jacobian_inverse_is_exact_at_the_singularity(theta: float) -> None:
    eta = np.array([0.0, 0.0, 0.0, 0.3, theta, 0.5])
    j_inv = neurov.jacobian_inverse(eta)
    np.testing.assert_allclose(j_inv[:3, :3] @ j_inv[:3, :3].T, np.eye(3), atol=1e-14)
    np.testing.assert_allclose(j_inv, ref.jacobian_inverse(eta), atol=1e-15)
    # T^-1 loses rank there: the roll and yaw rates become indistinguishable.
    assert np.linalg.matrix_rank(j_inv, tol=1e-12) == 5


def test_is_near_singularity() -> None:
    threshold = neurov.singularity_threshold()
    assert threshold == pytest.approx(np.sqrt(np.finfo(float).eps))
    pose = np.zeros(6)
    for theta, expected in [
        (0.0, False),
        (1.0, False),
        (np.pi, False),
        (np.pi / 2 - 1e-6, False),  # |cos| = 1e-6, well above the threshold
        (np.pi / 2 - 0.5 * threshold, True),
        (np.pi / 2, True),
        (-np.pi / 2, True),
        (-np.pi / 2 + 0.5 * threshold, True),
    ]:
        pose[4] = theta
        assert neurov.is_near_singularity(pose) is expected, theta
    # Just outside the threshold J is still computed.
    pose[4] = np.pi / 2 - 1e-6
    assert np.all(np.isfinite(neurov.jacobian(pose)))


def test_jacobian_dot_matches_central_difference(rng: np.random.Generator) -> None:
    """J_dot(eta, nu) = d/dt J(eta(t)) along eta_dot = J(eta) nu."""
    h = 1e-6
    for _ in range(N_POINTS):
        eta = ref.random_pose(rng, max_pitch=1.2)
        nu = ref.random_velocity(rng)
        eta_dot = neurov.jacobian(eta) @ nu
        numeric = (neurov.jacobian(eta + h * eta_dot) - neurov.jacobian(eta - h * eta_dot)) / (2 * h)
        analytic = neurov.jacobian_dot(eta, nu)
        np.testing.assert_allclose(analytic, numeric, rtol=1e-6, atol=1e-7)


def test_jacobian_dot_depends_linearly_on_the_angular_rates_only(rng: np.random.Generator) -> None:
    eta = ref.random_pose(rng)
    nu = ref.random_velocity(rng)
    j_dot = neurov.jacobian_dot(eta, nu)
    assert np.abs(j_dot).max() > 0.1
    np.testing.assert_allclose(neurov.jacobian_dot(eta, 2.5 * nu), 2.5 * j_dot, rtol=1e-13, atol=1e-14)
    other_linear = nu.copy()
    other_linear[:3] = [5.0, -7.0, 9.0]
    np.testing.assert_array_equal(neurov.jacobian_dot(eta, other_linear), j_dot)
    np.testing.assert_array_equal(neurov.jacobian_dot(eta, np.zeros(6)), np.zeros((6, 6)))


def test_singularity_threshold_is_what_the_functions_use() -> None:
    t = neurov.singularity_threshold()
    # cos(pi/2 - d) = sin(d) ~ d.
    inside = np.array([0.0, 0.0, 0.0, 0.0, np.pi / 2 - 0.9 * t, 0.0])
    outside = np.array([0.0, 0.0, 0.0, 0.0, np.pi / 2 - 1.1 * t, 0.0])
    assert neurov.is_near_singularity(inside)
    assert not neurov.is_near_singularity(outside)
    with pytest.raises(ValueError, match="'eta'"):
        neurov.jacobian(inside)
    assert np.isfinite(neurov.jacobian(outside)).all()


def test_to_body_is_the_inverse_jacobian_of_each_pose(rng: np.random.Generator) -> None:
    from neurov import _core

    eta = np.array([np.concatenate([rng.normal(size=3), random_angles(rng)]) for _ in range(5)])
    vectors = rng.normal(size=(5, 3, 6))
    out = _core.to_body(eta, vectors)
    assert out.shape == (5, 3, 6)
    for k in range(5):
        np.testing.assert_allclose(out[k], vectors[k] @ neurov.jacobian_inverse(eta[k]).T, rtol=1e-14, atol=1e-14)
    with pytest.raises(ValueError, match=r"'vectors' must have shape \(5, M, 6\)"):
        _core.to_body(eta, vectors[:4])
    with pytest.raises(ValueError, match=r"'eta' must have shape \(K, 6\)"):
        _core.to_body(eta[:, :5], vectors)
    with pytest.raises(TypeError, match="'eta'"):
        _core.to_body(eta.astype(bool), vectors)
