"""neurov.control, the python-control bridge: the analytic linearisation
against A and B written out here from the vehicle parameters, the poles
against damping and restoring stiffness, the NonlinearIOSystem against
neurov.rk4_step, and a run as TimeResponseData under control.step_info."""

from __future__ import annotations

import numpy as np
import pytest

ct = pytest.importorskip("control", minversion="0.10")

import neurov  # noqa: E402
import neurov.control as nc  # noqa: E402
from neurov.config.scenario import CommandSpec, ControllerSpec, Scenario  # noqa: E402
from neurov.results.timeseries import Result  # noqa: E402
from neurov.running.simulation import simulate


def skew(a: np.ndarray) -> np.ndarray:
    return np.array([[0.0, -a[2], a[1]], [a[2], 0.0, -a[0]], [-a[1], a[0], 0.0]])


def mass_matrix(p: dict) -> np.ndarray:
    """M = M_RB + M_A (Fossen 2011, eq. 3.44) from the parameters."""
    s = skew(p["centre_of_gravity"])
    m = p["mass"]
    m_rb = np.block([[m * np.eye(3), -m * s], [m * s, p["inertia"]]])
    return m_rb + p["added_mass"]


def restoring_stiffness(p: dict) -> np.ndarray:
    """dg/deta at eta = 0, from Fossen's g(eta) (2011, eq. 4.6) at small
    angles: sin(a) ~ a, cos(a) ~ 1."""
    w, b = p["weight"], p["buoyancy"]
    xg, yg, zg = p["centre_of_gravity"]
    xb, yb, zb = p["centre_of_buoyancy"]
    g = np.zeros((6, 6))
    g[1, 3] = -(w - b)                  # Y = -(W - B) cos(theta) sin(phi)
    g[3, 3] = zg * w - zb * b           # K = ... + (z_g W - z_b B) cos(theta) sin(phi)
    g[5, 3] = -(xg * w - xb * b)        # N = -(x_g W - x_b B) cos(theta) sin(phi) - ...
    g[0, 4] = w - b                     # X = (W - B) sin(theta)
    g[4, 4] = zg * w - zb * b           # M = (z_g W - z_b B) sin(theta) + ...
    g[5, 4] = -(yg * w - yb * b)        # N = ... - (y_g W - y_b B) sin(theta)
    return g


def linear_model_at_rest(p: dict) -> tuple[np.ndarray, np.ndarray]:
    """A and B at eta = nu = 0: J(0) = I, C(nu) nu is quadratic so has no
    linear part, D(0) = D_L."""
    m_inv = np.linalg.inv(mass_matrix(p))
    a = np.zeros((12, 12))
    a[:6, 6:] = np.eye(6)
    a[6:, :6] = -m_inv @ restoring_stiffness(p)
    a[6:, 6:] = -m_inv @ np.diag(p["linear_damping"])
    b = np.vstack([np.zeros((6, 6)), m_inv])
    return a, b


VEHICLES = ["nerov", "bluerov2_heavy"]


@pytest.mark.parametrize("preset", VEHICLES)
def test_linearisation_at_rest_is_the_analytic_a_and_b(preset: str) -> None:
    vehicle = neurov.Vehicle.preset(preset)
    sys = nc.linearize(vehicle, np.zeros(6), np.zeros(6))
    a, b = linear_model_at_rest(vehicle.parameters())
    np.testing.assert_allclose(sys.A, a, rtol=0, atol=1e-12 * np.abs(a).max())
    np.testing.assert_allclose(sys.B, b, rtol=0, atol=1e-12 * np.abs(b).max())
    np.testing.assert_array_equal(sys.C, np.eye(12))
    np.testing.assert_array_equal(sys.D, np.zeros((12, 6)))


def test_signals_are_named() -> None:
    names = ["x", "y", "z", "phi", "theta", "psi", "u", "v", "w", "p", "q", "r"]
    inputs = ["tau_X", "tau_Y", "tau_Z", "tau_K", "tau_M", "tau_N"]
    nerov = neurov.Vehicle.nerov()
    for sys in (nc.linearize(nerov, np.zeros(6), np.zeros(6)), nc.nonlinear_system(nerov)):
        assert sys.state_labels == names
        assert sys.output_labels == names
        assert sys.input_labels == inputs
    assert nc.nonlinear_system(nerov).isctime() and nc.linearize(nerov, np.zeros(6), np.zeros(6)).isctime()


def test_linearisation_away_from_rest_matches_differences_of_the_dynamics(rng: np.random.Generator) -> None:
    """At a moving, tilted state in a current A and B are the derivatives of
    the same right-hand side the NonlinearIOSystem integrates (checks that the
    binding passes eta, nu, tau and current in their places)."""
    vehicle = neurov.Vehicle.preset("bluerov2_heavy")
    eta = np.array([1.0, -2.0, 3.0, 0.3, -0.4, 1.1])
    nu = rng.uniform(-1.0, 1.0, 6)
    tau = rng.uniform(-50.0, 50.0, 6)
    current = np.array([0.4, -0.3, 0.1])
    sys = nc.linearize(vehicle, eta, nu, tau, current)
    x = np.concatenate([eta, nu])

    def f(x: np.ndarray, tau: np.ndarray) -> np.ndarray:
        return neurov._core.plant_derivative(vehicle, x[:6], x[6:], tau, current)

    h = 1e-6
    a_fd = np.column_stack([(f(x + h * e, tau) - f(x - h * e, tau)) / (2 * h) for e in np.eye(12)])
    b_fd = np.column_stack([(f(x, tau + h * e) - f(x, tau - h * e)) / (2 * h) for e in np.eye(6)])
    np.testing.assert_allclose(sys.A, a_fd, rtol=0, atol=1e-6 * np.abs(a_fd).max())
    np.testing.assert_allclose(sys.B, b_fd, rtol=0, atol=1e-6 * np.abs(b_fd).max())
    # tau enters affinely: the operating force does not change the model.
    other = nc.linearize(vehicle, eta, nu, -tau, current)
    np.testing.assert_array_equal(other.A, sys.A)


def match_poles(computed: np.ndarray, expected: list[complex]) -> float:
    """Largest distance between the two pole sets, each expected pole paired
    with its nearest computed one (each used once)."""
    left = list(computed)
    worst = 0.0
    for pole in expected:
        i = int(np.argmin([abs(c - pole) for c in left]))
        worst = max(worst, abs(left.pop(i) - pole))
    return worst


def test_poles_are_damping_and_restoring_stiffness() -> None:
    """NEROV at rest: x, y, z and psi integrate (poles at 0); surge, sway,
    heave and yaw decay at -d/(m + m_a) (no restoring force there, W = B);
    roll and pitch are damped pendulums, eig [[0, 1], [-k/I, -d/I]] with
    k = z_g W - z_b B and I the moment of inertia plus its added inertia."""
    vehicle = neurov.Vehicle.nerov()
    p = vehicle.parameters()
    assert p["weight"] == p["buoyancy"]
    total = np.diag(mass_matrix(p))
    d = p["linear_damping"]
    k = p["centre_of_gravity"][2] * p["weight"] - p["centre_of_buoyancy"][2] * p["buoyancy"]
    expected: list[complex] = [0.0] * 4
    expected += [-d[i] / total[i] for i in (0, 1, 2, 5)]
    for i in (3, 4):
        expected += list(np.linalg.eigvals(np.array([[0.0, 1.0], [-k / total[i], -d[i] / total[i]]])))
    poles = nc.linearize(vehicle, np.zeros(6), np.zeros(6)).poles()
    assert len(poles) == 12
    assert match_poles(poles, expected) <= 1e-12 * max(abs(e) for e in expected)
    # Roll and pitch are underdamped: the pendulum pairs are complex.
    assert np.count_nonzero(np.abs(poles.imag) > 0.1) == 4


@pytest.mark.parametrize("current", [None, np.array([0.3, -0.2, 0.1])], ids=["still", "current"])
def test_nonlinear_system_matches_rk4_step(current: np.ndarray | None) -> None:
    """control.input_output_response of the NonlinearIOSystem (scipy's
    adaptive RK45 at tight tolerances) against neurov.rk4_step with a small
    fixed step, both from a moving, tilted state under a constant force."""
    vehicle = neurov.Vehicle.nerov()
    eta0 = np.array([1.0, -2.0, 3.0, 0.2, -0.15, 0.6])
    nu0 = np.array([0.5, -0.3, 0.2, 0.1, -0.08, 0.15])
    tau = np.array([40.0, -30.0, 20.0, 5.0, -8.0, 6.0])
    t = np.linspace(0.0, 4.0, 401)
    sys = nc.nonlinear_system(vehicle, current)
    response = ct.input_output_response(
        sys, t, np.tile(tau[:, None], (1, t.size)), np.concatenate([eta0, nu0]),
        solve_ivp_method="RK45", solve_ivp_kwargs={"rtol": 1e-12, "atol": 1e-12})
    assert response.success
    eta, nu = eta0, nu0
    rk4 = [np.concatenate([eta, nu])]
    substeps = 10
    for _ in range(t.size - 1):
        for _ in range(substeps):
            eta, nu = neurov.rk4_step(vehicle, eta, nu, tau, (t[1] - t[0]) / substeps, current)
        rk4.append(np.concatenate([eta, nu]))
    rk4_states = np.array(rk4).T
    np.testing.assert_allclose(response.states, rk4_states, rtol=0, atol=1e-9 * np.abs(rk4_states).max())
    np.testing.assert_array_equal(response.outputs, response.states)


def test_bad_arguments_name_themselves() -> None:
    nerov = neurov.Vehicle.nerov()
    with pytest.raises(TypeError, match="'vehicle'"):
        nc.linearize("nerov", np.zeros(6), np.zeros(6))  # type: ignore[arg-type]
    with pytest.raises(TypeError, match="'vehicle'"):
        nc.nonlinear_system(None)  # type: ignore[arg-type]
    with pytest.raises(ValueError, match="'current'"):
        nc.nonlinear_system(nerov, current=[0.1, 0.2])
    with pytest.raises(ValueError, match="'nu'"):
        nc.linearize(nerov, np.zeros(6), [0.0, np.nan, 0, 0, 0, 0])
    with pytest.raises(ValueError, match="'tau'"):
        nc.linearize(nerov, np.zeros(6), np.zeros(6), tau0=np.zeros(5))
    with pytest.raises(ValueError, match="singularity"):
        nc.linearize(nerov, [0, 0, 0, 0, np.pi / 2, 0], np.zeros(6))
    with pytest.raises(TypeError, match="'result'"):
        nc.to_time_response({"t": [0.0]})  # type: ignore[arg-type]


# --- a run as TimeResponseData ----------------------------------------------------


@pytest.fixture(scope="module")
def heave_step() -> Result:
    """PD on NEROV, commanded from rest to 1 m depth (smoothed by the reference model)."""
    target = np.array([0.0, 0.0, 1.0, 0.0, 0.0, 0.0])
    command = CommandSpec(type="waypoints", times=np.array([0.0]), poses=target[None, :])
    scenario = Scenario(name="heave_step", duration=40.0, command=command,
                        controller=ControllerSpec(type="pd", kp=np.full(6, 200.0), kd=np.full(6, 300.0)))
    return simulate(scenario)


def test_time_response_holds_the_run(heave_step: Result) -> None:
    response = heave_step.to_time_response()
    assert isinstance(response, ct.TimeResponseData)
    np.testing.assert_array_equal(response.time, heave_step.t)
    np.testing.assert_array_equal(response.outputs, np.hstack([heave_step.eta, heave_step.nu]).T)
    np.testing.assert_array_equal(response.states, response.outputs)
    np.testing.assert_array_equal(response.inputs, heave_step.tau_applied.T)
    assert response.output_labels == list(nc.STATE_NAMES)
    assert response.input_labels == list(nc.INPUT_NAMES)


def test_step_info_of_a_run(heave_step: Result) -> None:
    """control.step_info on the run's depth against the same figures read
    off the arrays directly."""
    response = heave_step.to_time_response()
    z = response.outputs[response.output_labels.index("z")]
    info = ct.step_info(z, response.time)
    t, depth = heave_step.t, heave_step.eta[:, 2]
    final = depth[-1]
    assert final == pytest.approx(1.0, abs=0.01)
    rise = t[np.argmax(depth >= 0.9 * final)] - t[np.argmax(depth >= 0.1 * final)]
    outside = np.nonzero(np.abs(depth - final) > 0.02 * abs(final))[0]
    assert info["SteadyStateValue"] == final
    assert info["RiseTime"] == pytest.approx(rise, rel=1e-12)
    assert info["SettlingTime"] == pytest.approx(t[outside[-1] + 1], rel=1e-12)
    assert info["Peak"] == pytest.approx(np.max(np.abs(depth)), rel=1e-12)
    assert info["Overshoot"] == pytest.approx(max(0.0, 100 * (np.max(depth) - final) / final), abs=1e-9)
    assert 0 < info["RiseTime"] < info["SettlingTime"] < t[-1]


def test_time_response_plots(heave_step: Result) -> None:
    """python-control draws the run: outputs on one axes, inputs on another."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    try:
        plot = heave_step.to_time_response().plot(overlay_signals=True)
        assert plot.lines.shape == (2, 1)
        outputs, inputs = plot.lines[0, 0], plot.lines[1, 0]
        assert [line.get_label().split(",")[0] for line in outputs] == list(nc.STATE_NAMES)
        assert [line.get_label().split(",")[0] for line in inputs] == list(nc.INPUT_NAMES)
        np.testing.assert_array_equal(outputs[2].get_ydata(), heave_step.eta[:, 2])
        np.testing.assert_array_equal(inputs[2].get_ydata(), heave_step.tau_applied[:, 2])
    finally:
        plt.close("all")
