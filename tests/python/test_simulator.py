"""The simulator stepped from Python (`_core.Simulator`) and the run
configuration bound field by field (`_core.SimulationConfig`).

A run driven step by step from Python with a built-in controller must give
exactly the arrays of `run_closed_loop` (the all-C++ loop) on a scenario with
thrusters and a failure, a current step, measurement noise and sensor faults:
the simulator is the one code path of both.
"""

from __future__ import annotations

import copy
import pickle
from pathlib import Path
from typing import Any

import numpy as np
import pytest

import neurov
from neurov import _core
from neurov.config.scenario import ControllerSpec, CurrentStep, SensorFault, ThrusterFailure
from neurov.laws.registry import build_controller
from neurov.running.plant import build_vehicle, simulation_config

ROOT = Path(__file__).resolve().parents[2]
DURATION = 60.0


def busy_scenario() -> neurov.Scenario:
    """Thrusters with a failure and a repair, a current step, noise and three sensor faults."""
    s = neurov.load_scenario(ROOT / "examples" / "scenarios" / "faults" / "thruster_failure.toml")
    return s.replace(
        duration=DURATION,
        thruster_failures=[ThrusterFailure(index=0, efficiency=0.0, time=20.0),
                           ThrusterFailure(index=0, efficiency=1.0, time=35.0)],
        current_steps=[CurrentStep(time=15.0, velocity=np.array([0.2, -0.1, 0.0]))],
        noise_eta=np.full(6, 0.01),
        noise_nu=np.full(6, 0.005),
        sensor_faults=[
            SensorFault(kind=neurov.SensorFaultKind.freeze, start=10.0, end=11.0, nu=False),
            SensorFault(kind=neurov.SensorFaultKind.dropout, start=25.0, end=26.0, eta=False),
            SensorFault(kind=neurov.SensorFaultKind.noise_burst, start=40.0, end=44.0, noise_eta=np.full(6, 0.05)),
        ],
    )


CONTROLLERS = {
    "nn": ControllerSpec(type="nn", modification="sigma", sigma_m=0.05),
    "linear": ControllerSpec(type="linear", theta0="scaled", theta0_scale=0.8),
    "pd": ControllerSpec(type="pd", kp=np.array([200.0, 200, 200, 50, 50, 50])),
}


def report(controller: Any) -> dict[str, Any]:
    """What the C++ loop logs of a built-in controller, read from Python."""
    if isinstance(controller, _core.NNAdaptiveController):
        return {"adaptive_norm": controller.weight_norm}
    if isinstance(controller, _core.LinearAdaptiveController):
        return {"adaptive_norm": float(np.linalg.norm(controller.theta)), "parameters": controller.theta}
    return {}


def drive(sim: _core.Simulator, controller: Any) -> None:
    """The closed loop, written in Python around the simulator."""
    while not sim.done:
        o = sim.observation
        try:
            tau = controller.step(o.eta, o.nu, o.eta_d, o.eta_d_dot, o.eta_d_ddot)
            status = _core.Status.ok
        except ValueError:
            # The controllers refuse a NaN measurement (a dropout) and stay as they were.
            assert not (np.all(np.isfinite(o.eta)) and np.all(np.isfinite(o.nu)))
            tau, status = np.full(6, np.nan), _core.Status.non_finite_input
        sim.step(tau, status=status, s=controller.s, **report(controller))


def same_arrays(a: dict[str, Any], b: dict[str, Any], *, close: tuple[str, ...] = ()) -> None:
    assert set(a) == set(b)
    for key in a:
        if key in close:
            np.testing.assert_allclose(a[key], b[key], rtol=1e-12, atol=0, err_msg=key)
        else:
            np.testing.assert_array_equal(a[key], b[key], err_msg=key)


@pytest.fixture(scope="module")
def scenario() -> neurov.Scenario:
    return busy_scenario()


@pytest.mark.parametrize("name", list(CONTROLLERS))
def test_a_run_stepped_from_python_is_the_closed_loop(scenario: neurov.Scenario, name: str) -> None:
    spec = CONTROLLERS[name]
    vehicle, config = build_vehicle(scenario), simulation_config(scenario)
    expected = _core.run_closed_loop(vehicle, build_controller(spec, scenario), config)
    # The scenario reaches what it is meant to test.
    assert not expected["diverged"] and len(expected["t"]) == round(DURATION / scenario.dt) + 1
    assert {1, 2, 4, 8} <= {int(b) for f in expected["faults"] for b in (1, 2, 4, 8) if f & b}
    assert np.count_nonzero(expected["controller_status"]) >= 5

    controller = build_controller(spec, scenario)
    sim = _core.Simulator(vehicle, config, logged_parameters=expected["theta"].shape[1])
    drive(sim, controller)
    # Eigen's ||theta|| and numpy's may round apart; everything else is bitwise.
    same_arrays(sim.result(), expected, close=("adaptive_norm",) if name == "linear" else ())
    assert sim.steps == sim.planned_steps == len(expected["t"])
    eta, nu = sim.state
    assert np.all(np.isfinite(eta)) and np.all(np.isfinite(nu))


def test_reset_replays_the_run_and_a_new_seed_changes_the_noise(scenario: neurov.Scenario) -> None:
    vehicle, config = build_vehicle(scenario), simulation_config(scenario)
    sim = _core.Simulator(vehicle, config)
    controller = build_controller(CONTROLLERS["pd"], scenario)
    drive(sim, controller)
    first = sim.result()
    sim.reset()
    assert sim.steps == 0 and not sim.done and sim.observation.t == 0.0
    assert len(sim.result()["t"]) == 0
    controller.reset()
    drive(sim, controller)
    same_arrays(sim.result(), first)
    sim.reset(seed=config.seed + 1)
    controller.reset()
    drive(sim, controller)
    other = sim.result()
    assert not np.array_equal(other["eta"], first["eta"])
    np.testing.assert_array_equal(other["eta"][0], first["eta"][0])  # the true start is the same


def test_step_after_done_is_an_error_and_loses_nothing() -> None:
    config = _core.SimulationConfig(duration=1.0, command=_core.Command(times=[0.0], poses=[[1.0, 0, 0, 0, 0, 0]]))
    sim = _core.Simulator(_core.Vehicle.nerov(), config)
    while not sim.done:
        assert sim.step(np.full(6, 10.0)) == _core.Status.ok
    before = sim.result()
    assert len(before["t"]) == 6
    with pytest.raises(RuntimeError, match="run is done.*6 rows"):
        sim.step(np.zeros(6))
    same_arrays(sim.result(), before)
    assert sim.steps == 6


@pytest.mark.parametrize(
    ("tau", "error", "match"),
    [
        pytest.param(np.zeros(5), ValueError, r"'tau' must have shape \(6,\)", id="five forces"),
        pytest.param(np.zeros((6, 1)), ValueError, r"'tau' must have shape \(6,\)", id="a column"),
        pytest.param([0, 0, np.nan, 0, 0, 0], ValueError, "'tau' must be finite", id="NaN"),
        pytest.param([0, 0, 0, np.inf, 0, 0], ValueError, "'tau' must be finite", id="Inf"),
        pytest.param("thrust", TypeError, "'tau'", id="a string"),
        pytest.param(None, TypeError, "'tau'", id="None"),
    ],
)
def test_bad_tau_is_an_error_and_changes_nothing(tau: Any, error: type[Exception], match: str) -> None:
    config = _core.SimulationConfig(duration=1.0, command=_core.Command(times=[0.0], poses=[[1.0, 0, 0, 0, 0, 0]]))
    sim = _core.Simulator(_core.Vehicle.nerov(), config)
    sim.step(np.ones(6))
    eta, nu = sim.state
    with pytest.raises(error, match=match):
        sim.step(tau)
    assert sim.steps == 1
    np.testing.assert_array_equal(sim.state[0], eta)
    np.testing.assert_array_equal(sim.state[1], nu)


def test_refused_steps_follow_the_policy() -> None:
    """A refused step's force is ignored (NaN allowed): zero, or the last accepted one."""
    for policy, expected in ((_core.RefusedStepPolicy.zero, np.zeros(6)),
                             (_core.RefusedStepPolicy.hold, np.arange(6.0))):
        config = _core.SimulationConfig(duration=1.0, refused_step_policy=policy,
                                        command=_core.Command(times=[0.0], poses=[[0.0] * 6]))
        sim = _core.Simulator(_core.Vehicle.nerov(), config)
        sim.step(np.arange(6.0))
        sim.step(np.full(6, np.nan), status=_core.Status.non_finite_input, s=np.full(6, np.nan))
        r = sim.result()
        np.testing.assert_array_equal(r["tau_demanded"][1], expected)
        assert list(r["controller_status"]) == [0, int(_core.Status.non_finite_input)]
        assert np.all(np.isnan(r["s"][1]))


def test_logged_parameters_are_checked() -> None:
    config = _core.SimulationConfig(duration=1.0, command=_core.Command(times=[0.0], poses=[[0.0] * 6]))
    sim = _core.Simulator(_core.Vehicle.nerov(), config, logged_parameters=3)
    with pytest.raises(ValueError, match=r"'parameters' must have shape \(3,\)"):
        sim.step(np.zeros(6))
    with pytest.raises(ValueError, match=r"'parameters' must have shape \(3,\)"):
        sim.step(np.zeros(6), parameters=[1.0, 2.0])
    sim.step(np.zeros(6), parameters=[1.0, 2.0, 3.0], adaptive_norm=7.0)
    r = sim.result()
    np.testing.assert_array_equal(r["theta"], [[1.0, 2.0, 3.0]])
    np.testing.assert_array_equal(r["adaptive_norm"], [7.0])
    with pytest.raises(ValueError, match="logged_parameters"):
        _core.Simulator(_core.Vehicle.nerov(), config, logged_parameters=-1)


def test_a_bad_configuration_names_the_field() -> None:
    config = _core.SimulationConfig(dt=-0.1, command=_core.Command(times=[0.0], poses=[[0.0] * 6]))
    with pytest.raises(ValueError, match="dt = -0.1: expected > 0"):
        _core.Simulator(_core.Vehicle.nerov(), config)


def test_the_run_diverges_and_keeps_its_rows() -> None:
    huge = _core.SinusoidalDisturbance(dof=0, amplitude=1e306, phase=1.5, start=0.6)
    config = _core.SimulationConfig(duration=5.0, disturbances=[huge],
                                    command=_core.Command(times=[0.0], poses=[[0.0] * 6]))
    sim = _core.Simulator(_core.Vehicle.nerov(), config)
    while not sim.done:
        status = sim.step(np.zeros(6))
    assert sim.diverged and status != _core.Status.ok
    r = sim.result()
    assert r["diverged"] and len(r["t"]) == sim.steps == 4
    with pytest.raises(RuntimeError, match="diverged"):
        sim.step(np.zeros(6))


# ------------------------------------------------------- the bound configuration


def test_config_defaults_are_the_cpp_ones() -> None:
    c = _core.SimulationConfig()
    assert (c.dt, c.substeps, c.duration, c.current_period, c.seed) == (0.2, 10, 60.0, 0.0, 0)
    np.testing.assert_array_equal(c.lambda_d, np.ones(6))
    np.testing.assert_array_equal(c.omega, np.full(6, 0.25))
    assert c.refused_step_policy == _core.RefusedStepPolicy.zero and not c.use_thrusters
    assert c.disturbances == () and c.command.linear
    assert c.thrusters.saturation == _core.Saturation.scale


def test_fixed_size_fields_are_views_and_others_are_assigned_whole() -> None:
    c = _core.SimulationConfig()
    c.noise_eta[2] = 0.5  # a view into the C++ struct
    assert c.noise_eta[2] == 0.5
    c.command.times = [0.0, 1.0]  # a nested struct is a reference into its parent
    np.testing.assert_array_equal(c.command.times, [0.0, 1.0])
    with pytest.raises(ValueError, match="read-only"):
        c.command.times[0] = 3.0
    c.sensor_faults = [_core.SensorFault(start=1.0, end=2.0)]
    c.sensor_faults[0].end = 5.0  # changes a copy
    assert c.sensor_faults[0].end == 2.0
    with pytest.raises(AttributeError):
        c.sensor_faults.append(_core.SensorFault())  # type: ignore[attr-defined]
    c.sensor_faults = [*c.sensor_faults, _core.SensorFault(kind=_core.SensorFaultKind.dropout)]
    assert [f.kind for f in c.sensor_faults] == [_core.SensorFaultKind.freeze, _core.SensorFaultKind.dropout]


@pytest.mark.parametrize(
    ("make", "error", "match"),
    [
        pytest.param(lambda: _core.SimulationConfig(dtt=0.1), TypeError, "unexpected keyword argument 'dtt'", id="typo"),
        pytest.param(lambda: _core.SimulationConfig(substeps=2.5), TypeError, "SimulationConfig.substeps must be an int",
                     id="float substeps"),
        pytest.param(lambda: _core.SimulationConfig(seed=-1), ValueError, "SimulationConfig.seed must be >= 0",
                     id="negative seed"),
        pytest.param(lambda: _core.SimulationConfig(dt="fast"), TypeError, "SimulationConfig.dt must be a real number",
                     id="str dt"),
        pytest.param(lambda: _core.SimulationConfig(use_thrusters=1), TypeError, "use_thrusters must be a bool",
                     id="int bool"),
        pytest.param(lambda: _core.SimulationConfig(eta0=np.zeros(5)), ValueError,
                     r"SimulationConfig.eta0 must have shape \(6,\), got \(5,\)", id="short eta0"),
        pytest.param(lambda: _core.SimulationConfig(eta0="x"), TypeError, "SimulationConfig.eta0", id="str eta0"),
        pytest.param(lambda: _core.Command(poses=np.zeros(6)), ValueError, r"Command.poses must have shape \(n, 6\)",
                     id="poses of one dimension"),
        pytest.param(lambda: _core.SimulationConfig(sensor_faults=[{"kind": "freeze"}]), TypeError,
                     r"SimulationConfig.sensor_faults\[0\] must be a SensorFault, got dict", id="a dict for a fault"),
        pytest.param(lambda: _core.SimulationConfig(current_steps=_core.CurrentStep()), TypeError,
                     "SimulationConfig.current_steps must be a list of CurrentStep", id="one step, not a list"),
        pytest.param(lambda: _core.SensorFault(kind="freeze"), TypeError,
                     "SensorFault.kind must be a SensorFaultKind, got str", id="a str for an enum"),
        pytest.param(lambda: _core.ThrusterConfig(matrix=np.eye(5)), ValueError,
                     r"ThrusterConfig.matrix must have shape \(6, m\)", id="thruster matrix of 5 rows"),
    ],
)
def test_a_field_of_the_wrong_type_or_shape_is_named(make: Any, error: type[Exception], match: str) -> None:
    with pytest.raises(error, match=match):
        make()


def test_validate_speaks_for_the_cpp_validator() -> None:
    c = _core.SimulationConfig(command=_core.Command(times=[0.0], poses=[[0.0] * 6]))
    c.validate()
    c.noise_nu[3] = -1.0
    with pytest.raises(ValueError, match=r"SimulationConfig: noise_nu\[3\] = -1: expected >= 0"):
        c.validate()
    t = _core.ThrusterConfig(matrix=np.eye(6), max_thrust=np.ones(6), min_thrust=np.ones(6))
    with pytest.raises(ValueError, match=r"ThrusterConfig: thrusters.max_thrust\[0\] = 1"):
        t.validate()


def test_a_config_copies_and_pickles_with_every_field(scenario: neurov.Scenario) -> None:
    config = simulation_config(scenario)
    for other in (copy.copy(config), copy.deepcopy(config), pickle.loads(pickle.dumps(config))):
        assert repr(other) == repr(config)
        assert other.sensor_faults[1].kind == _core.SensorFaultKind.dropout
        np.testing.assert_array_equal(other.thrusters.matrix, config.thrusters.matrix)
    other = copy.copy(config)
    other.noise_eta[0] = 1.0
    assert config.noise_eta[0] == 0.01  # a copy, not a view of the original
