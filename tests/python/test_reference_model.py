"""neurov.ReferenceModel (eq. 12-13): nu_d_dot = -Lambda_d nu_d + J^T(eta_d) Omega (r - eta_d),
eta_d_dot = J(eta_d) nu_d. One DOF on its own (every other DOF at zero) is
exactly x'' + lambda_d x' + omega (x - r) = 0, whose step response is known in
closed form; a general command settles on r."""

from __future__ import annotations

import numpy as np
import pytest

import neurov
from neurov import _core


def second_order(t: np.ndarray, lam: float, om: float, x0: float, r: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """x'' + lam x' + om (x - r) = 0 from rest at x0: (x, x', x'') at t."""
    wn, z, step = np.sqrt(om), lam / (2 * np.sqrt(om)), r - x0
    if abs(z - 1) < 1e-12:
        e = np.exp(-wn * t) * (1 + wn * t)
        de = -wn * wn * t * np.exp(-wn * t)
    elif z < 1:
        wd = wn * np.sqrt(1 - z * z)
        e = np.exp(-z * wn * t) * (np.cos(wd * t) + z * wn / wd * np.sin(wd * t))
        de = -np.exp(-z * wn * t) * wn * wn / wd * np.sin(wd * t)
    else:
        s1, s2 = -wn * (z - np.sqrt(z * z - 1)), -wn * (z + np.sqrt(z * z - 1))
        e = (s1 * np.exp(s2 * t) - s2 * np.exp(s1 * t)) / (s1 - s2)
        de = s1 * s2 * (np.exp(s2 * t) - np.exp(s1 * t)) / (s1 - s2)
    x = x0 + step * (1 - e)
    v = -step * de
    return x, v, om * (r - x) - lam * v


def run(model: neurov.ReferenceModel, r: np.ndarray, dt: float, steps: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    out = [model.step(r, dt) for _ in range(steps)]
    return tuple(np.array([o[i] for o in out]) for i in range(3))  # type: ignore[return-value]


# zeta = lambda_d / (2 sqrt(omega)): 0.3, 0.7, 1 (critical), 1.5, on every DOF.
CASES = [(0, 0.6, 1.0), (1, 1.4, 1.0), (2, 4.0, 4.0), (3, 1.2, 4.0), (4, 6.0, 4.0), (5, 0.9, 2.25), (5, 0.42, 0.49)]


@pytest.mark.parametrize(("dof", "lam", "om"), CASES)
def test_single_dof_step_is_the_analytic_second_order_response(dof: int, lam: float, om: float) -> None:
    x0, r_val = (0.1, 0.6) if dof >= 3 else (0.2, 1.2)
    lambda_d, omega = np.full(6, 1.7), np.full(6, 0.8)
    lambda_d[dof], omega[dof] = lam, om
    eta0, r = np.zeros(6), np.zeros(6)
    eta0[dof], r[dof] = x0, r_val
    model = neurov.ReferenceModel(lambda_d, omega, eta0)
    dt, steps = 0.01, 1000
    eta_d, eta_d_dot, eta_d_ddot = run(model, r, dt, steps)
    t = dt * np.arange(1, steps + 1)
    x, v, a = second_order(t, lam, om, x0, r_val)
    step = r_val - x0
    # RK4 truncation at omega_n dt <= 0.02 is ~1e-9 of the step.
    np.testing.assert_allclose(eta_d[:, dof], x, rtol=0, atol=1e-8 * step)
    np.testing.assert_allclose(eta_d_dot[:, dof], v, rtol=0, atol=1e-7 * step)
    np.testing.assert_allclose(eta_d_ddot[:, dof], a, rtol=0, atol=1e-7 * step * max(1.0, om))
    others = np.delete(np.hstack([eta_d, eta_d_dot, eta_d_ddot]).reshape(steps, 3, 6), dof, axis=2)
    np.testing.assert_array_equal(others, 0.0)
    # Overshoot from zeta alone; the sampled peak is within |x''| dt^2 / 8 of it.
    zeta = lam / (2 * np.sqrt(om))
    overshoot = (eta_d[:, dof].max() - r_val) / step
    if zeta < 1:
        assert overshoot == pytest.approx(np.exp(-zeta * np.pi / np.sqrt(1 - zeta**2)), abs=2e-5)
    else:
        assert overshoot <= 1e-12


def test_general_command_settles_on_r() -> None:
    lambda_d = np.array([2, 3, 2.5, 4, 3.5, 2.0])
    omega = np.array([1, 2, 1.5, 4, 3, 1.2])
    r = np.array([1, -2, 0.5, 0.3, -0.2, 1.0])
    model = neurov.ReferenceModel(lambda_d, omega, [-0.5, 0.4, 0, -0.1, 0.1, -0.5])
    eta_d, eta_d_dot, eta_d_ddot = run(model, r, 0.02, 3000)
    np.testing.assert_allclose(eta_d[-1], r, rtol=0, atol=1e-9)
    np.testing.assert_allclose(model.eta_d, r, rtol=0, atol=1e-9)
    np.testing.assert_allclose(model.nu_d, 0, atol=1e-9)
    np.testing.assert_allclose(eta_d_dot[-1], 0, atol=1e-9)
    np.testing.assert_allclose(eta_d_ddot[-1], 0, atol=1e-9)
    np.testing.assert_array_equal(model.lambda_d, lambda_d)
    np.testing.assert_array_equal(model.omega, omega)


def test_desired_derivatives_are_time_derivatives_of_eta_d() -> None:
    model = neurov.ReferenceModel([1.5, 2, 2.5, 1.8, 2.2, 1.6], [1, 1.5, 2, 2.5, 1.2, 0.9])
    dt = 1e-3
    eta_d, eta_d_dot, eta_d_ddot = run(model, np.array([2, -1, 0.5, 0.4, -0.3, 1.2]), dt, 2000)
    v_fd = (eta_d[2:] - eta_d[:-2]) / (2 * dt)
    a_fd = (eta_d_dot[2:] - eta_d_dot[:-2]) / (2 * dt)
    np.testing.assert_allclose(v_fd, eta_d_dot[1:-1], atol=1e-5)
    np.testing.assert_allclose(a_fd, eta_d_ddot[1:-1], atol=1e-5)
    assert np.abs(eta_d_ddot).max() > 0.5


# ------------------------------------------------------------------ bad input


def state(model: neurov.ReferenceModel) -> bytes:
    return model.eta_d.tobytes() + model.nu_d.tobytes()


@pytest.mark.parametrize("bad", [np.nan, np.inf, -np.inf])
@pytest.mark.parametrize("index", [0, 3, 5])
def test_non_finite_command_names_r_and_changes_nothing(bad: float, index: int) -> None:
    model = neurov.ReferenceModel(np.full(6, 2.0), np.ones(6))
    r = np.array([1, 2, -1, 0.2, 0.1, 0.5])
    for _ in range(5):
        model.step(r, 0.1)
    before = state(model)
    r_bad = r.copy()
    r_bad[index] = bad
    with pytest.raises(ValueError, match="'r'"):
        model.step(r_bad, 0.1)
    assert state(model) == before
    # It carries on exactly as a model that never saw the bad command.
    twin = neurov.ReferenceModel(np.full(6, 2.0), np.ones(6))
    for _ in range(5):
        twin.step(r, 0.1)
    np.testing.assert_array_equal(model.step(r, 0.1)[0], twin.step(r, 0.1)[0])


@pytest.mark.parametrize("dt", [0.0, -0.1, np.nan, np.inf])
def test_bad_dt_names_dt_and_changes_nothing(dt: float) -> None:
    model = neurov.ReferenceModel(np.full(6, 2.0), np.ones(6))
    model.step(np.ones(6), 0.1)
    before = state(model)
    with pytest.raises(ValueError, match="'dt'"):
        model.step(np.ones(6), dt)
    assert state(model) == before


@pytest.mark.parametrize(
    ("r", "error", "match"),
    [(np.ones(5), ValueError, r"'r' must have shape \(6,\)"), (None, TypeError, "'r'"), ("abc", TypeError, "'r'")],
)
def test_malformed_command_names_r(r: object, error: type, match: str) -> None:
    model = neurov.ReferenceModel(np.full(6, 2.0), np.ones(6))
    with pytest.raises(error, match=match):
        model.step(r, 0.1)


def test_singular_pitch_is_refused_and_changes_nothing() -> None:
    model = neurov.ReferenceModel(np.full(6, 2.0), np.ones(6))
    model.reset([0, 0, 0, 0, np.pi / 2, 0])
    before = state(model)
    with pytest.raises(ValueError, match="singularity"):
        model.step(np.ones(6), 0.05)
    assert state(model) == before


def test_reset_returns_to_rest_and_refuses_non_finite() -> None:
    model = neurov.ReferenceModel(np.full(6, 2.0), np.ones(6))
    model.step(np.ones(6), 0.5)
    model.reset(np.full(6, 0.25))
    np.testing.assert_array_equal(model.eta_d, 0.25)
    np.testing.assert_array_equal(model.nu_d, 0.0)
    with pytest.raises(ValueError, match="'eta0'"):
        model.reset([0, 0, np.nan, 0, 0, 0])
    np.testing.assert_array_equal(model.eta_d, 0.25)


@pytest.mark.parametrize(
    ("kwargs", "match"),
    [
        ({"lambda_d": [1, 1, 0, 1, 1, 1]}, r"lambda_d\[2\] = 0"),
        ({"lambda_d": [-1, 1, 1, 1, 1, 1]}, r"lambda_d\[0\] = -1"),
        ({"lambda_d": [1, 1, 1, 1, 1, np.nan]}, "'lambda_d' must be finite"),
        ({"lambda_d": [1, 1, 1]}, r"'lambda_d' must have shape \(6,\)"),
        ({"omega": [1, 1, 1, 0, 1, 1]}, r"omega\[3\] = 0"),
        ({"omega": [1, -0.5, 1, 1, 1, 1]}, r"omega\[1\] = -0.5"),
        ({"eta0": [0, 0, 0, 0, np.pi / 2, 0]}, r"eta0\[4\]"),
        ({"eta0": [np.inf, 0, 0, 0, 0, 0]}, "'eta0' must be finite"),
    ],
)
def test_invalid_configuration_names_the_parameter(kwargs: dict, match: str) -> None:
    args = {"lambda_d": np.ones(6), "omega": np.ones(6), "eta0": np.zeros(6)} | kwargs
    with pytest.raises(ValueError, match=match):
        neurov.ReferenceModel(**args)


# ------------------------------------------------------------------ pitch limit

PITCH_LIMIT = np.pi / 2 - 0.2  # ReferenceModel::pitch_limit(), 90 deg - kPitchMargin


def pitch_run(model: neurov.ReferenceModel, pitch: float, dt: float, steps: int) -> tuple[np.ndarray, np.ndarray]:
    """Steps with a command of the given pitch (other DOF zero): the reference's
    pitch and pitch_limited after each step."""
    r = np.zeros(6)
    r[4] = pitch
    out = [(model.step(r, dt)[0][4], model.pitch_limited) for _ in range(steps)]
    return np.array([o[0] for o in out]), np.array([o[1] for o in out])


def test_pitch_limited_is_false_after_construction_and_for_a_level_command() -> None:
    model = neurov.ReferenceModel(np.full(6, 1.0), np.full(6, 0.25))
    assert model.pitch_limited is False
    pitch, limited = pitch_run(model, 0.0, 0.2, 200)
    assert not limited.any()
    np.testing.assert_array_equal(pitch, 0.0)
    # A command inside the limit is not limited either.
    pitch, limited = pitch_run(model, 1.0, 0.2, 400)
    assert not limited.any()
    assert pitch[-1] == pytest.approx(1.0, abs=1e-6)


@pytest.mark.parametrize("lam", [1.0, 0.3])  # 0.3: underdamped (zeta 0.3), would overshoot the limit
@pytest.mark.parametrize("sign", [1.0, -1.0])
def test_pitch_beyond_the_limit_is_held_at_it_and_commanding_back_returns(lam: float, sign: float) -> None:
    model = neurov.ReferenceModel(np.full(6, lam), np.full(6, 0.25))
    pitch, limited = pitch_run(model, sign * 1.5, 0.2, 400)
    assert limited.any()
    assert np.all(np.abs(pitch) <= PITCH_LIMIT + 1e-9)
    assert sign * pitch[-1] == pytest.approx(PITCH_LIMIT, abs=1e-6)
    assert model.pitch_limited
    # Back to level: the pitch returns below 0.1 rad and the flag clears.
    pitch, limited = pitch_run(model, 0.0, 0.2, 400)
    assert np.all(np.abs(pitch) <= PITCH_LIMIT + 1e-9)
    assert np.abs(pitch[-1]) < 0.1
    assert not model.pitch_limited
    # A reset clears it too.
    pitch_run(model, sign * 1.5, 0.2, 5)
    assert model.pitch_limited
    model.reset(np.zeros(6))
    assert model.pitch_limited is False


def closed_loop_pitch(poses: list[list[float]], times: list[float]) -> dict:
    kd = np.full(6, 100.0)
    config = _core.SimulationConfig(dt=0.2, duration=80.0, lambda_d=np.full(6, 1.0), omega=np.full(6, 0.25),
                                    command=_core.Command(times=times, poses=poses, linear=False))
    return neurov.run_closed_loop(neurov.Vehicle.nerov(), neurov.PDController(kd, kd), config)


def test_closed_loop_reports_a_pitch_limited_reference_in_the_fault_bits() -> None:
    """Fault bit 16: the row's eta_d came from a pitch-limited reference step,
    exactly as a ReferenceModel stepped with the same command reports it."""
    up, level = [0, 0, 0, 0, 1.5, 0], [0, 0, 0, 0, 0, 0]
    r = closed_loop_pitch([up, level], [0.0, 40.1])
    assert not r["diverged"]
    bit = (r["faults"] & 16) != 0
    assert np.all(r["faults"] & ~np.uint8(16) == 0)
    assert np.all(np.abs(r["eta_d"][:, 4]) <= PITCH_LIMIT + 1e-9)
    model = neurov.ReferenceModel(np.full(6, 1.0), np.full(6, 0.25))
    expected = [False]  # row 0: the reference as created
    for t in r["t"][:-1]:
        model.step(up if t < 40.1 else level, 0.2)
        expected.append(model.pitch_limited)
    np.testing.assert_array_equal(bit, expected)
    # Row k's eta_d is from the step at t_{k-1}: rows 1 to 201 (t_{k-1} <= 40 s) follow the 1.5 rad command.
    assert not bit[0] and bit[1:202].all()
    assert not bit[-1] and abs(r["eta_d"][-1, 4]) < 0.1
    # A level command never sets it.
    level_run = closed_loop_pitch([level, [1, 0, 0, 0, 0, 0.5]], [0.0, 10.1])
    assert np.all(level_run["faults"] == 0)
