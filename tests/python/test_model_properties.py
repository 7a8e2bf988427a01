"""Property-based tests (Hypothesis) of the model through the Python API:
the kinematic identities (rotation, J, J^-1, J-dot, the pitch singularity)
and the vehicle's Coriolis matrix."""

from __future__ import annotations

from typing import Any

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

import neurov
import reference_model as ref
from property_strategies import SETTINGS, angle, finite, pitch, poses, vectors, velocities

# ------------------------------------------------------------------ kinematics


@SETTINGS
@given(finite(-10, 10), finite(-10, 10), finite(-10, 10))
def test_rotation_is_a_proper_rotation_for_any_angles(phi: float, theta: float, psi: float) -> None:
    # Any angles, the singularity and beyond included: R has no division.
    r = neurov.rotation(phi, theta, psi)
    np.testing.assert_allclose(r @ r.T, np.eye(3), atol=1e-14)
    assert np.linalg.det(r) == pytest.approx(1.0, abs=1e-14)
    np.testing.assert_allclose(r, ref.rotation(phi, theta, psi), atol=1e-14)


@SETTINGS
@given(poses())
def test_jacobian_inverse_inverts_the_jacobian(eta: np.ndarray) -> None:
    j, j_inv = neurov.jacobian(eta), neurov.jacobian_inverse(eta)
    scale = 1.0 / abs(np.cos(eta[4]))
    np.testing.assert_allclose(j_inv @ j, np.eye(6), atol=1e-14 * scale**2)
    np.testing.assert_allclose(j @ j_inv, np.eye(6), atol=1e-14 * scale**2)


@SETTINGS
@given(poses(), poses())
def test_jacobian_depends_on_the_attitude_only(a: np.ndarray, b: np.ndarray) -> None:
    b = b.copy()
    b[3:] = a[3:]
    np.testing.assert_array_equal(neurov.jacobian(a), neurov.jacobian(b))


@SETTINGS
@given(poses(pitch=finite(-1.3, 1.3)), velocities)
def test_jacobian_dot_is_the_time_derivative_along_the_motion(eta: np.ndarray, nu: np.ndarray) -> None:
    h = 1e-6
    eta_dot = neurov.jacobian(eta) @ nu
    numeric = (neurov.jacobian(eta + h * eta_dot) - neurov.jacobian(eta - h * eta_dot)) / (2 * h)
    scale = 1.0 / np.cos(eta[4]) ** 3
    np.testing.assert_allclose(neurov.jacobian_dot(eta, nu), numeric, atol=1e-6 * scale * (1 + np.abs(nu).max()) ** 2)


@SETTINGS
@given(finite(-np.pi, np.pi), st.sampled_from([-1.0, 1.0]), st.integers(0, 3))
def test_singularity_is_refused_by_j_and_j_dot_not_by_j_inverse(phi: float, sign: float, turns: int) -> None:
    eta = np.array([0.0, 0.0, 0.0, phi, sign * np.pi / 2 + 2 * np.pi * turns, 0.3])
    assert neurov.is_near_singularity(eta)
    with pytest.raises(ValueError, match="singularity"):
        neurov.jacobian(eta)
    with pytest.raises(ValueError, match="singularity"):
        neurov.jacobian_dot(eta, np.ones(6))
    assert np.all(np.isfinite(neurov.jacobian_inverse(eta)))


# ------------------------------------------------------------ vehicle model


@st.composite
def vehicles(draw: st.DrawFn) -> dict[str, Any]:
    """Physically valid random vehicles: SPD inertia about the origin (parallel
    axes), SPD full added mass, any W, B, r_g, r_b, both Coriolis forms."""
    mass = draw(finite(5.0, 500.0))
    rg = draw(vectors(3, -0.1, 0.1))
    a = draw(vectors(9, -1.0, 1.0)).reshape(3, 3)
    s = np.array([[0, -rg[2], rg[1]], [rg[2], 0, -rg[0]], [-rg[1], rg[0], 0]])
    inertia = a @ a.T + draw(finite(0.5, 50.0)) * np.eye(3) + mass * s.T @ s
    b = draw(vectors(36, -2.0, 2.0)).reshape(6, 6)
    added = b @ b.T + draw(finite(0.5, 50.0)) * np.eye(6)
    return {
        "mass": mass,
        "inertia": 0.5 * (inertia + inertia.T),
        "weight": mass * 9.81,
        "buoyancy": mass * 9.81 * draw(finite(0.9, 1.1)),
        "added_mass": 0.5 * (added + added.T),
        "linear_damping": draw(vectors(6, 0.0, 100.0)),
        "quadratic_damping": draw(vectors(6, 0.0, 200.0)),
        "centre_of_gravity": rg,
        "centre_of_buoyancy": rg + draw(vectors(3, -0.05, 0.05)),
        "coriolis_form": draw(st.sampled_from(["velocity_independent", "kirchhoff"])),
    }


@SETTINGS
@given(vehicles(), vectors(6, -3.0, 3.0))
def test_coriolis_is_skew_symmetric_and_does_no_work(params: dict[str, Any], nu: np.ndarray) -> None:
    v = neurov.Vehicle(**params)
    c = v.coriolis(nu)
    size = np.abs(c).max() + 1.0
    np.testing.assert_allclose(c + c.T, np.zeros((6, 6)), atol=1e-13 * size)
    assert abs(nu @ c @ nu) <= 1e-12 * size * (nu @ nu)
    m = v.mass_matrix()
    np.testing.assert_array_equal(m, m.T)
    assert np.linalg.eigvalsh(m).min() > 0
    d = v.damping(nu)
    assert nu @ d @ nu >= 0


@SETTINGS
@given(vehicles(), vectors(6, -3.0, 3.0))
def test_both_coriolis_forms_move_the_plant_alike(params: dict[str, Any], nu: np.ndarray) -> None:
    a = neurov.Vehicle(**{**params, "coriolis_form": "velocity_independent"})
    b = neurov.Vehicle(**{**params, "coriolis_form": "kirchhoff"})
    fa, fb = a.coriolis(nu) @ nu, b.coriolis(nu) @ nu
    np.testing.assert_allclose(fa, fb, atol=1e-12 * (1 + np.abs(fa).max()))
