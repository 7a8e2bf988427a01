"""rk4_step: agreement with a numpy RK4, energy, convergence order, steady state."""

from __future__ import annotations

from typing import Any

import numpy as np
import pytest

import neurov
import reference_model as ref


def numpy_rk4_step(
    vehicle: neurov.Vehicle,
    eta: np.ndarray,
    nu: np.ndarray,
    tau: np.ndarray,
    dt: float,
    current: np.ndarray | None = None,
) -> tuple[np.ndarray, np.ndarray]:
    """Classical RK4 in numpy on eta_dot = J(eta) nu (numpy J) and the core's acceleration."""

    def f(e: np.ndarray, n: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        return ref.jacobian(e) @ n, vehicle.acceleration(e, n, tau, current)

    return ref.rk4(f, eta, nu, dt)


def energy(vehicle: neurov.Vehicle, eta: np.ndarray, nu: np.ndarray) -> float:
    """Kinetic plus potential energy. With r_g = 0 and W = B the restoring
    moments derive from U = zm (1 - cos(phi) cos(theta)), zm = z_g W - z_b B:
    dU/dt = g(eta) . nu."""
    assert not np.any(vehicle.centre_of_gravity) and vehicle.weight == vehicle.buoyancy
    zm = -vehicle.centre_of_buoyancy[2] * vehicle.buoyancy
    kinetic = 0.5 * nu @ vehicle.mass_matrix() @ nu
    return float(kinetic + zm * (1.0 - np.cos(eta[3]) * np.cos(eta[4])))


def undamped(parameters: dict[str, Any], **changes: Any) -> neurov.Vehicle:
    p = dict(parameters, linear_damping=np.zeros(6), quadratic_damping=np.zeros(6))
    p.update(changes)
    return neurov.Vehicle(**p)


# ------------------------------------------------------- python and C++ agree


def test_rk4_step_matches_numpy_rk4(general_vehicle: neurov.Vehicle, rng: np.random.Generator) -> None:
    for _ in range(20):
        eta, nu = ref.random_pose(rng), ref.random_velocity(rng)
        tau = rng.normal(scale=100.0, size=6)
        dt = rng.uniform(0.01, 0.3)
        got = neurov.rk4_step(general_vehicle, eta, nu, tau, dt)
        want = numpy_rk4_step(general_vehicle, eta, nu, tau, dt)
        np.testing.assert_allclose(got[0], want[0], rtol=1e-12, atol=1e-12)
        np.testing.assert_allclose(got[1], want[1], rtol=1e-12, atol=1e-12)
        # and it actually moved.
        assert np.abs(got[0] - eta).max() > 1e-3


def test_rk4_step_matches_numpy_rk4_in_a_current(nerov: neurov.Vehicle, rng: np.random.Generator) -> None:
    for _ in range(20):
        eta, nu = ref.random_pose(rng), ref.random_velocity(rng)
        tau = rng.normal(scale=100.0, size=6)
        current = rng.normal(scale=0.5, size=3)
        got = neurov.rk4_step(nerov, eta, nu, tau, 0.2, current)
        want = numpy_rk4_step(nerov, eta, nu, tau, 0.2, current)
        np.testing.assert_allclose(got[0], want[0], rtol=1e-12, atol=1e-12)
        np.testing.assert_allclose(got[1], want[1], rtol=1e-12, atol=1e-12)
        still = neurov.rk4_step(nerov, eta, nu, tau, 0.2)
        assert np.abs(still[1] - got[1]).max() > 1e-4  # the current matters


def test_rk4_step_matches_fully_independent_numpy_model(rng: np.random.Generator) -> None:
    """No neurov inside the reference: numpy J, numpy acceleration, numpy RK4."""
    vehicle = neurov.Vehicle(**ref.NEROV)
    for _ in range(20):
        eta, nu = ref.random_pose(rng), ref.random_velocity(rng)
        tau = rng.normal(scale=100.0, size=6)

        def f(e: np.ndarray, n: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
            return ref.jacobian(e) @ n, ref.acceleration(ref.NEROV, e, n, tau)  # noqa: B023

        got = neurov.rk4_step(vehicle, eta, nu, tau, 0.2)
        want = ref.rk4(f, eta, nu, 0.2)
        np.testing.assert_allclose(np.r_[got], np.r_[want], rtol=1e-11, atol=1e-11)


def test_rk4_step_returns_new_arrays_and_leaves_inputs_alone(nerov: neurov.Vehicle) -> None:
    eta = np.array([1.0, 2.0, 3.0, 0.1, 0.2, 0.3])
    nu = np.array([0.5, -0.2, 0.1, 0.05, -0.03, 0.02])
    tau = np.array([10.0, 0, 0, 0, 0, 1.0])
    copies = eta.copy(), nu.copy(), tau.copy()
    new_eta, new_nu = neurov.rk4_step(nerov, eta, nu, tau, 0.1)
    for before, after in zip(copies, (eta, nu, tau)):
        np.testing.assert_array_equal(before, after)
    assert new_eta.shape == new_nu.shape == (6,)
    assert new_eta.dtype == new_nu.dtype == np.float64
    assert new_eta.flags.writeable and new_nu.flags.writeable
    assert not np.shares_memory(new_eta, eta) and not np.shares_memory(new_nu, nu)


def test_rest_is_an_equilibrium(nerov: neurov.Vehicle) -> None:
    eta = np.array([5.0, -3.0, 10.0, 0.0, 0.0, 1.0])
    new_eta, new_nu = neurov.rk4_step(nerov, eta, np.zeros(6), np.zeros(6), 0.2)
    np.testing.assert_array_equal(new_eta, eta)
    np.testing.assert_array_equal(new_nu, np.zeros(6))


def test_rk4_step_refuses_the_pitch_singularity(nerov: neurov.Vehicle) -> None:
    eta = np.array([0.0, 0.0, 0.0, 0.0, np.pi / 2, 0.0])
    with pytest.raises(ValueError, match="'eta'.*singularity"):
        neurov.rk4_step(nerov, eta, np.full(6, 0.1), np.zeros(6), 0.1)


def test_rk4_step_overflow_raises(nerov: neurov.Vehicle) -> None:
    with pytest.raises(ValueError, match="overflow"):
        neurov.rk4_step(nerov, np.zeros(6), np.full(6, 1e150), np.zeros(6), 1.0)


# ------------------------------------------------------------------- energy


@pytest.mark.parametrize("form", ["velocity_independent", "kirchhoff"])
def test_energy_is_conserved_without_damping_or_restoring(form: str, rng: np.random.Generator) -> None:
    """Zero damping, W = B, r_b = r_g = 0: only 1/2 nu^T M nu, which C(nu) cannot change."""
    vehicle = undamped(
        ref.general_parameters(form),
        centre_of_gravity=np.zeros(3),
        centre_of_buoyancy=np.zeros(3),
        weight=1800.0,
        buoyancy=1800.0,
    )
    assert not np.any(vehicle.restoring(ref.random_pose(rng)))
    eta0, nu0 = ref.random_pose(rng, max_pitch=0.5), ref.random_velocity(rng, scale=0.5)
    e0 = energy(vehicle, eta0, nu0)

    def max_drift(dt: float, t_end: float = 25.0) -> tuple[float, np.ndarray]:
        eta, nu, drift = eta0, nu0, 0.0
        for _ in range(round(t_end / dt)):
            eta, nu = neurov.rk4_step(vehicle, eta, nu, np.zeros(6), dt)
            drift = max(drift, abs(energy(vehicle, eta, nu) - e0))
        return drift, nu

    coarse, _ = max_drift(0.05)
    fine, nu = max_drift(0.025)
    assert fine < 2e-8 * e0
    # What drift there is, is the integrator's truncation error: it shrinks with dt.
    assert fine < coarse / 10
    # The motion was not trivial: the Coriolis terms turned the velocity.
    assert np.abs(nu - nu0).max() > 0.05


@pytest.mark.parametrize("form", ["velocity_independent", "kirchhoff"])
def test_energy_with_restoring_is_conserved_without_damping(form: str, rng: np.random.Generator) -> None:
    """NEROV undamped: kinetic plus the potential energy of its metacentric height."""
    vehicle = undamped(dict(ref.NEROV, coriolis_form=form))
    eta = np.array([0.0, 0.0, 0.0, 0.4, -0.3, 0.0])
    nu = ref.random_velocity(rng, scale=0.3)
    e0 = energy(vehicle, eta, nu)
    kinetic_min = np.inf
    drift = 0.0
    for _ in range(1000):
        eta, nu = neurov.rk4_step(vehicle, eta, nu, np.zeros(6), 0.05)
        drift = max(drift, abs(energy(vehicle, eta, nu) - e0))
        kinetic_min = min(kinetic_min, float(0.5 * nu @ vehicle.mass_matrix() @ nu))
    assert drift < 1e-6 * e0
    # Kinetic energy alone is not conserved: energy moved into the potential.
    assert kinetic_min < 0.9 * (e0 - 36.0 * (1 - np.cos(0.4) * np.cos(-0.3)))


def test_damping_dissipates_energy(nerov: neurov.Vehicle, rng: np.random.Generator) -> None:
    eta = np.array([0.0, 0.0, 0.0, 0.4, -0.3, 0.0])
    nu = ref.random_velocity(rng, scale=0.5)
    e_prev = e0 = energy(nerov, eta, nu)
    for _ in range(300):
        eta, nu = neurov.rk4_step(nerov, eta, nu, np.zeros(6), 0.05)
        e = energy(nerov, eta, nu)
        assert e < e_prev
        e_prev = e
    assert e_prev < 0.1 * e0


# ------------------------------------------------------------- convergence


def test_fourth_order_convergence(rng: np.random.Generator) -> None:
    """Error at T = 2 s ~ dt^4: halving dt divides it by ~16. Quadratic damping
    is left out because |nu| nu is not smooth where a velocity changes sign."""
    vehicle = neurov.Vehicle(**dict(ref.general_parameters(), quadratic_damping=np.zeros(6)))
    eta0 = ref.random_pose(rng, max_pitch=0.5)
    nu0 = ref.random_velocity(rng, scale=0.5)
    tau = rng.normal(scale=50.0, size=6)

    def run(dt: float, t_end: float = 2.0) -> np.ndarray:
        eta, nu = eta0, nu0
        for _ in range(round(t_end / dt)):
            eta, nu = neurov.rk4_step(vehicle, eta, nu, tau, dt)
        return np.r_[eta, nu]

    reference = run(0.2 / 64)
    errors = [np.linalg.norm(run(dt) - reference) for dt in (0.2, 0.1, 0.05)]
    ratios = [errors[0] / errors[1], errors[1] / errors[2]]
    assert all(14.0 < r < 18.5 for r in ratios), (errors, ratios)


# ------------------------------------------------------------ steady state


def test_constant_surge_thrust_reaches_terminal_velocity(nerov: neurov.Vehicle) -> None:
    """70 u + 100 u^2 = F: F = 170 N gives u = 1 m/s; eta advances along the heading."""
    psi = 0.7
    eta, nu = np.array([0.0, 0.0, 0.0, 0.0, 0.0, psi]), np.zeros(6)
    tau = np.array([170.0, 0, 0, 0, 0, 0])
    for _ in range(300):
        eta, nu = neurov.rk4_step(nerov, eta, nu, tau, 0.2)
    np.testing.assert_allclose(nu, [1.0, 0, 0, 0, 0, 0], atol=1e-9)
    np.testing.assert_allclose(eta[3:], [0.0, 0.0, psi], atol=1e-12)
    direction = eta[:2] / np.linalg.norm(eta[:2])
    np.testing.assert_allclose(direction, [np.cos(psi), np.sin(psi)], atol=1e-12)
    assert eta[2] == pytest.approx(0.0, abs=1e-12)
