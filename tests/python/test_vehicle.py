"""The vehicle model M nu_dot + C(nu) nu + D(nu) nu + g(eta) = tau, checked against
the numbers of docs/model.md and against an independent numpy implementation."""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

import numpy as np
import pytest

import neurov
import reference_model as ref
from controller_reference import nerov_c

N_POINTS = 40


def assert_parameters_equal(a: Mapping[str, Any], b: Mapping[str, Any]) -> None:
    assert a.keys() == b.keys()
    for key in a:
        if isinstance(a[key], np.ndarray):
            np.testing.assert_array_equal(a[key], b[key], err_msg=key)
        else:
            assert a[key] == b[key], key


# ---------------------------------------------------------------- NEROV numbers


def test_nerov_mass_matrix(nerov: neurov.Vehicle) -> None:
    m = nerov.mass_matrix()
    assert m.shape == (6, 6)
    np.testing.assert_array_equal(m, np.diag([215.0, 265.0, 265.0, 40.0, 80.0, 80.0]))


def test_nerov_damping(nerov: neurov.Vehicle, rng: np.random.Generator) -> None:
    np.testing.assert_array_equal(nerov.damping(np.zeros(6)), np.diag([70, 100, 100, 30, 50, 50]))
    for _ in range(N_POINTS):
        u, v, w, p, q, r = nu = ref.random_velocity(rng)
        expected = np.diag(
            [
                70 + 100 * abs(u),
                100 + 200 * abs(v),
                100 + 200 * abs(w),
                30 + 50 * abs(p),
                50 + 100 * abs(q),
                50 + 100 * abs(r),
            ]
        )
        np.testing.assert_allclose(nerov.damping(nu), expected, rtol=1e-15)
        # D(nu) = D(-nu): it depends on |nu|.
        np.testing.assert_array_equal(nerov.damping(-nu), nerov.damping(nu))


def test_nerov_restoring(nerov: neurov.Vehicle, rng: np.random.Generator) -> None:
    for _ in range(N_POINTS):
        eta = ref.random_pose(rng, max_pitch=np.pi)
        ph, th = eta[3], eta[4]
        expected = [0, 0, 0, 36 * np.cos(th) * np.sin(ph), 36 * np.sin(th), 0]
        np.testing.assert_allclose(nerov.restoring(eta), expected, rtol=1e-13, atol=1e-13)


def test_nerov_restoring_rights_the_vehicle(nerov: neurov.Vehicle) -> None:
    """Rolled to starboard (phi > 0), g acts as +K in M nu_dot = tau - g: it rolls back."""
    g = nerov.restoring([0, 0, 0, 0.2, 0, 0])
    assert g[3] > 0
    g = nerov.restoring([0, 0, 0, 0, -0.2, 0])
    assert g[4] < 0


def test_nerov_coriolis_is_eq_39(nerov: neurov.Vehicle, rng: np.random.Generator) -> None:
    for _ in range(N_POINTS):
        nu = ref.random_velocity(rng)
        np.testing.assert_allclose(nerov.coriolis(nu), nerov_c(nu), rtol=1e-14, atol=1e-12)


def test_nerov_matches_spec_parameters(nerov: neurov.Vehicle) -> None:
    p = nerov.parameters()
    assert p["mass"] == 185.0
    np.testing.assert_array_equal(p["inertia"], np.diag([25.0, 50.0, 50.0]))
    np.testing.assert_array_equal(p["centre_of_gravity"], [0, 0, 0])
    np.testing.assert_array_equal(p["centre_of_buoyancy"], [0, 0, -0.02])
    assert p["weight"] == p["buoyancy"] == 1800.0
    np.testing.assert_array_equal(p["added_mass"], np.diag([30.0, 80, 80, 15, 30, 30]))
    assert p["coriolis_form"] == "velocity_independent"


def test_properties_agree_with_parameters(general_vehicle: neurov.Vehicle) -> None:
    p = general_vehicle.parameters()
    for key, value in p.items():
        got = getattr(general_vehicle, key)
        if isinstance(value, np.ndarray):
            np.testing.assert_array_equal(got, value, err_msg=key)
        else:
            assert got == value, key


# ------------------------------------------------------ general model properties


def test_mass_matrix_matches_reference(
    general_vehicle: neurov.Vehicle, general_parameters: dict[str, Any]
) -> None:
    m = general_vehicle.mass_matrix()
    np.testing.assert_allclose(m, ref.mass_matrix(general_parameters), rtol=1e-15, atol=1e-15)
    np.testing.assert_array_equal(m, m.T)
    assert np.linalg.eigvalsh(m).min() > 0


def test_coriolis_is_skew_symmetric_and_does_no_work(
    general_vehicle: neurov.Vehicle, nerov: neurov.Vehicle, rng: np.random.Generator
) -> None:
    for vehicle in (general_vehicle, nerov):
        for _ in range(N_POINTS):
            nu = ref.random_velocity(rng, scale=2.0)
            c = vehicle.coriolis(nu)
            assert np.abs(c).max() > 1.0  # not trivially zero
            np.testing.assert_allclose(c, -c.T, rtol=0, atol=1e-12)
            assert nu @ c @ nu == pytest.approx(0.0, abs=1e-10)


def test_coriolis_matches_reference(
    general_vehicle: neurov.Vehicle, general_parameters: dict[str, Any], rng: np.random.Generator
) -> None:
    for _ in range(N_POINTS):
        nu = ref.random_velocity(rng)
        np.testing.assert_allclose(
            general_vehicle.coriolis(nu), ref.coriolis(general_parameters, nu), rtol=1e-13, atol=1e-12
        )


def test_coriolis_forms_give_the_same_force_but_different_matrices(rng: np.random.Generator) -> None:
    a = neurov.Vehicle(**ref.general_parameters("velocity_independent"))
    b = neurov.Vehicle(**ref.general_parameters("kirchhoff"))
    assert a.coriolis_form == "velocity_independent" and b.coriolis_form == "kirchhoff"
    for _ in range(N_POINTS):
        nu = ref.random_velocity(rng)
        np.testing.assert_allclose(a.coriolis(nu) @ nu, b.coriolis(nu) @ nu, rtol=1e-12, atol=1e-11)
        assert np.abs(a.coriolis(nu) - b.coriolis(nu)).max() > 1.0


def test_restoring_matches_reference(
    general_vehicle: neurov.Vehicle, general_parameters: dict[str, Any], rng: np.random.Generator
) -> None:
    for _ in range(N_POINTS):
        eta = ref.random_pose(rng, max_pitch=np.pi)
        np.testing.assert_allclose(
            general_vehicle.restoring(eta), ref.restoring(general_parameters, eta), rtol=1e-13, atol=1e-12
        )


def test_acceleration_solves_the_equation_of_motion(
    general_vehicle: neurov.Vehicle, rng: np.random.Generator
) -> None:
    """nu_dot = solve(M, tau - C nu - D nu - g) with the vehicle's own M, C, D, g."""
    v = general_vehicle
    for _ in range(N_POINTS):
        eta, nu, tau = ref.random_pose(rng), ref.random_velocity(rng), rng.normal(scale=100, size=6)
        expected = np.linalg.solve(
            v.mass_matrix(), tau - v.coriolis(nu) @ nu - v.damping(nu) @ nu - v.restoring(eta)
        )
        np.testing.assert_allclose(v.acceleration(eta, nu, tau), expected, rtol=1e-11, atol=1e-12)


def test_acceleration_agrees_with_independent_numpy_model_nerov(
    nerov: neurov.Vehicle, rng: np.random.Generator
) -> None:
    for _ in range(N_POINTS):
        eta, nu, tau = ref.random_pose(rng), ref.random_velocity(rng), rng.normal(scale=100, size=6)
        np.testing.assert_allclose(
            nerov.acceleration(eta, nu, tau), ref.acceleration(ref.NEROV, eta, nu, tau), rtol=1e-11, atol=1e-12
        )


def test_acceleration_agrees_with_independent_numpy_model_general(
    general_vehicle: neurov.Vehicle, general_parameters: dict[str, Any], rng: np.random.Generator
) -> None:
    for _ in range(N_POINTS):
        eta, nu, tau = ref.random_pose(rng), ref.random_velocity(rng), rng.normal(scale=100, size=6)
        current = rng.normal(scale=0.5, size=3)
        np.testing.assert_allclose(
            general_vehicle.acceleration(eta, nu, tau),
            ref.acceleration(general_parameters, eta, nu, tau),
            rtol=1e-11,
            atol=1e-12,
        )
        np.testing.assert_allclose(
            general_vehicle.acceleration(eta, nu, tau, current),
            ref.acceleration(general_parameters, eta, nu, tau, current),
            rtol=1e-11,
            atol=1e-12,
        )


def test_nerov_at_rest_is_in_equilibrium(nerov: neurov.Vehicle) -> None:
    np.testing.assert_array_equal(nerov.acceleration(np.zeros(6), np.zeros(6), np.zeros(6)), np.zeros(6))
    # Pure surge thrust: acceleration F / (m - X_udot) in surge only.
    np.testing.assert_allclose(
        nerov.acceleration(np.zeros(6), np.zeros(6), [215.0, 0, 0, 0, 0, 0]), [1, 0, 0, 0, 0, 0], atol=1e-15
    )


# ---------------------------------------------------------------- round trips


@pytest.mark.parametrize("name", ["nerov", "bluerov2_heavy", "general"])
def test_parameters_round_trip(name: str, coriolis_form: str, rng: np.random.Generator) -> None:
    if name == "general":
        v = neurov.Vehicle(**ref.general_parameters(coriolis_form))
    else:
        p = neurov.Vehicle.preset(name).parameters()
        p["coriolis_form"] = coriolis_form  # type: ignore[typeddict-item]
        v = neurov.Vehicle(**p)
    w = neurov.Vehicle(**v.parameters())
    assert_parameters_equal(v.parameters(), w.parameters())
    np.testing.assert_array_equal(v.mass_matrix(), w.mass_matrix())
    eta, nu, tau = ref.random_pose(rng), ref.random_velocity(rng), rng.normal(size=6)
    np.testing.assert_array_equal(v.acceleration(eta, nu, tau), w.acceleration(eta, nu, tau))
    np.testing.assert_array_equal(v.coriolis(nu), w.coriolis(nu))


def test_parameters_returns_a_copy(nerov: neurov.Vehicle) -> None:
    p = nerov.parameters()
    p["inertia"][0, 0] = -1.0
    p["linear_damping"][:] = 0.0
    assert nerov.parameters()["inertia"][0, 0] == 25.0
    assert nerov.linear_damping[0] == 70.0
    nerov.added_mass[0, 0] = 0.0
    assert nerov.added_mass[0, 0] == 30.0


def test_diagonal_and_full_matrices_build_the_same_vehicle() -> None:
    p = dict(ref.NEROV)
    a = neurov.Vehicle(**p)
    p["inertia"] = np.diag(p["inertia"])
    p["added_mass"] = np.diag(p["added_mass"])
    b = neurov.Vehicle(**p)
    assert_parameters_equal(a.parameters(), b.parameters())


@pytest.mark.parametrize(("name", "entry"), [("inertia", (0, 1)), ("added_mass", (1, 4))])
def test_a_bad_matrix_entry_is_named_by_its_flat_index_in_every_check(name: str, entry: tuple[int, int]) -> None:
    """Entry (i, j) is index i * cols + j (numpy's flat index) whether it is
    NaN (the argument check) or breaks the symmetry (the C++ validation)."""
    p = dict(ref.NEROV)
    m = np.array(np.diag(p[name]) if np.ndim(p[name]) == 1 else p[name], dtype=float)
    flat = int(np.ravel_multi_index(entry, m.shape))
    for bad, match in [(5.0, rf"{name}\[{flat}\] = 5: expected a symmetric matrix"),
                       (np.nan, rf"'{name}' must be finite; element {flat} is nan")]:
        broken = m.copy()
        broken[entry] = bad
        with pytest.raises(ValueError, match=match):
            neurov.Vehicle(**{**p, name: broken})


def test_perturbed_copy_changes_the_model(nerov: neurov.Vehicle) -> None:
    p = nerov.parameters()
    p["mass"] = 200.0
    heavier = neurov.Vehicle(**p)
    assert heavier.mass_matrix()[0, 0] == 230.0
    assert nerov.mass_matrix()[0, 0] == 215.0


# ------------------------------------------------------------------- BlueROV2


def test_bluerov2_heavy_matches_spec() -> None:
    v = neurov.Vehicle.preset("bluerov2_heavy")
    assert v.mass == 13.5
    np.testing.assert_array_equal(v.inertia, np.diag([0.26, 0.23, 0.37]))
    np.testing.assert_array_equal(v.centre_of_gravity, [0, 0, 0])
    np.testing.assert_array_equal(v.centre_of_buoyancy, [0, 0, -0.01])
    np.testing.assert_array_equal(
        v.added_mass, np.diag([6.3567, 7.1206, 18.6863, 0.1858, 0.1348, 0.2215])
    )
    np.testing.assert_array_equal(v.linear_damping, [13.7, 0, 33.0, 0, 0.8, 0])
    np.testing.assert_array_equal(v.quadratic_damping, [141, 217, 190, 1.192, 0.470, 1.500])
    # W = m g and B = rho g V with V = 0.0134 m^3 (fresh to sea water).
    g = v.weight / v.mass
    assert 9.78 < g < 9.83
    rho = v.buoyancy / (g * 0.0134)
    assert 997.0 < rho < 1030.0
    np.testing.assert_allclose(
        v.mass_matrix(),
        np.diag([13.5 + 6.3567, 13.5 + 7.1206, 13.5 + 18.6863, 0.26 + 0.1858, 0.23 + 0.1348, 0.37 + 0.2215]),
        rtol=1e-15,
    )


def test_bluerov2_heavy_restoring(rng: np.random.Generator) -> None:
    v = neurov.Vehicle.preset("bluerov2_heavy")
    w, b = v.weight, v.buoyancy
    for _ in range(N_POINTS):
        eta = ref.random_pose(rng, max_pitch=np.pi)
        sf, cf, st, ct = np.sin(eta[3]), np.cos(eta[3]), np.sin(eta[4]), np.cos(eta[4])
        expected = [(w - b) * st, -(w - b) * ct * sf, -(w - b) * ct * cf, 0.01 * b * ct * sf, 0.01 * b * st, 0]
        np.testing.assert_allclose(v.restoring(eta), expected, rtol=1e-13, atol=1e-13)
    # In sea water (the preset's, 1025 kg/m^3) it displaces more than it
    # weighs: at rest and level it rises (z is down).
    assert v.acceleration(np.zeros(6), np.zeros(6), np.zeros(6))[2] < 0


# -------------------------------------------------------------------- current


def test_at_rest_in_a_current_it_accelerates_towards_the_current(
    nerov: neurov.Vehicle, rng: np.random.Generator
) -> None:
    for _ in range(N_POINTS):
        eta = ref.random_pose(rng)
        current = rng.normal(scale=0.5, size=3)
        nu_dot = nerov.acceleration(eta, np.zeros(6), np.zeros(6), current)
        # Earth-frame acceleration of the body origin.
        a_ned = neurov.rotation(*eta[3:]) @ nu_dot[:3]
        assert a_ned @ current > 0
        # and by exactly D(nu_r) / M along each body axis (w = 0, M and D diagonal).
        vc = neurov.rotation(*eta[3:]).T @ current
        lin = np.array([70.0, 100.0, 100.0]) + np.array([100.0, 200.0, 200.0]) * np.abs(vc)
        np.testing.assert_allclose(nu_dot[:3], lin * vc / [215.0, 265.0, 265.0], rtol=1e-12, atol=1e-14)


def test_moving_with_the_current_feels_no_drag(nerov: neurov.Vehicle, rng: np.random.Generator) -> None:
    for _ in range(10):
        psi = rng.uniform(-np.pi, np.pi)
        eta = np.array([0.0, 0.0, 0.0, 0.0, 0.0, psi])
        current = np.array([*rng.normal(size=2), 0.0])
        nu = np.r_[neurov.rotation(0.0, 0.0, psi).T @ current, np.zeros(3)]
        np.testing.assert_allclose(nerov.acceleration(eta, nu, np.zeros(6), current), np.zeros(6), atol=1e-13)
        # Without the current the same motion is damped.
        assert nerov.acceleration(eta, nu, np.zeros(6))[:3] @ nu[:3] < 0


def test_zero_current_is_no_current(general_vehicle: neurov.Vehicle, rng: np.random.Generator) -> None:
    eta, nu, tau = ref.random_pose(rng), ref.random_velocity(rng), rng.normal(size=6)
    a = general_vehicle.acceleration(eta, nu, tau)
    np.testing.assert_array_equal(general_vehicle.acceleration(eta, nu, tau, None), a)
    np.testing.assert_array_equal(general_vehicle.acceleration(eta, nu, tau, np.zeros(3)), a)
    np.testing.assert_array_equal(general_vehicle.acceleration(eta, nu, tau, current=[0, 0, 0]), a)


# ------------------------------------------------------------- overflow and pitch


def test_acceleration_overflow_raises(nerov: neurov.Vehicle) -> None:
    with pytest.raises(ValueError, match="overflow"):
        nerov.acceleration(np.zeros(6), np.full(6, 1e200), np.zeros(6))


@pytest.mark.parametrize("theta", [np.pi / 2, -np.pi / 2])
def test_acceleration_is_defined_at_the_pitch_singularity(nerov: neurov.Vehicle, theta: float) -> None:
    eta = np.array([0.0, 0.0, 0.0, 0.1, theta, 0.2])
    nu = np.full(6, 0.1)
    np.testing.assert_allclose(
        nerov.acceleration(eta, nu, np.zeros(6)), ref.acceleration(ref.NEROV, eta, nu, np.zeros(6)), atol=1e-12
    )
