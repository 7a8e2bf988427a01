"""Controllers written in Python: `neurov.Simulator` stepped by hand, and
`neurov.simulate` with a controller object.

The reference is the all-C++ loop (`run_closed_loop` with a built-in
controller): a Python controller that only delegates to a built-in one must
give the same run, on a scenario with thrusters, a current step, noise and
sensor faults. A controller that raises, returns the wrong shape or NaN is a
refused step, logged with its status; the run keeps every row.
"""

from __future__ import annotations

import dataclasses
from typing import Any

import numpy as np
import pytest

import neurov
from neurov import _core
from neurov.config.scenario import ControllerSpec
from neurov.laws.registry import build_controller
from neurov.running.plant import simulation_config
from neurov.study.spec import SCENARIO_DIR
from neurov.config.vehicle_file import load_vehicle_parameters
from test_simulator import busy_scenario
from user_controllers import factories

SPECS = {
    "nn": ControllerSpec(type="nn", modification="sigma", sigma_m=0.05),
    "linear": ControllerSpec(type="linear", theta0="scaled", theta0_scale=0.8),
    "pd": ControllerSpec(type="pd", kp=np.array([200.0, 200, 200, 50, 50, 50])),
    "pid": ControllerSpec(type="pid", kp=np.full(6, 100.0), ki=np.full(6, 5.0), kd=np.full(6, 200.0)),
    "smc": ControllerSpec(type="smc"),
}


def built_in(name: str, scenario: neurov.Scenario) -> Any:
    if name == "computed_torque":
        nominal = _core.Vehicle(**load_vehicle_parameters(scenario.vehicle_path()))
        return _core.ComputedTorqueController(nominal, np.ones(6), np.full(6, 50.0))
    return build_controller(SPECS[name], scenario)


NAMES = [*SPECS, *(["computed_torque"] if hasattr(_core, "ComputedTorqueController") else [])]


class Delegate(factories.Delegate):
    """A Python controller that hands every step to a built-in one (with the time keyword)."""

    def __init__(self, inner: Any) -> None:
        super().__init__(inner)
        self.times: list[float] = []

    def step(self, eta: Any, nu: Any, eta_d: Any, eta_d_dot: Any, eta_d_ddot: Any, *, t: float) -> Any:
        self.times.append(t)
        return super().step(eta, nu, eta_d, eta_d_dot, eta_d_ddot)


@pytest.fixture(scope="module")
def scenario() -> neurov.Scenario:
    return busy_scenario()


@pytest.mark.parametrize("name", NAMES)
def test_a_python_controller_delegating_to_a_built_in_one_is_the_cpp_run(scenario: neurov.Scenario,
                                                                          name: str) -> None:
    expected = neurov.simulate(scenario, built_in(name, scenario))
    assert not expected.diverged and len(expected.t) == round(scenario.duration / scenario.dt) + 1
    assert np.count_nonzero(expected.controller_status) >= 5  # the dropouts are refused steps
    assert np.any(expected.thrusts != 0)

    delegate = Delegate(built_in(name, scenario))
    got = neurov.simulate(scenario, delegate)
    np.testing.assert_allclose(got.eta, expected.eta, rtol=0, atol=1e-12)
    np.testing.assert_allclose(got.nu, expected.nu, rtol=0, atol=1e-12)
    np.testing.assert_allclose(got.tau_demanded, expected.tau_demanded, rtol=0, atol=1e-9)
    np.testing.assert_array_equal(got.s, expected.s)
    # A refused measurement (a dropout) is named as the C++ loop names it.
    np.testing.assert_array_equal(got.controller_status, expected.controller_status)
    assert delegate.times == pytest.approx(list(expected.t), abs=1e-12)
    assert got.controller == "Delegate"
    assert got.metrics()["refused_steps"] == expected.metrics()["refused_steps"]


def test_a_plain_object_with_only_step_runs(scenario: neurov.Scenario) -> None:
    class Only:
        def __init__(self) -> None:
            self.inner = built_in("pd", scenario)

        def step(self, eta: Any, nu: Any, eta_d: Any, eta_d_dot: Any, eta_d_ddot: Any) -> list[float]:
            return list(self.inner.step(eta, nu, eta_d, eta_d_dot, eta_d_ddot))

    assert isinstance(Only(), neurov.Controller)
    expected = neurov.simulate(scenario, built_in("pd", scenario))
    got = neurov.simulate(scenario, Only(), label="mine")
    np.testing.assert_allclose(got.eta, expected.eta, rtol=0, atol=1e-12)
    assert got.controller == "mine"
    assert np.all(np.isnan(got.s))  # no s given: not made up


# ----------------------------------------------------------- a controller that fails


def quiet_scenario(policy: str = "zero") -> neurov.Scenario:
    s = neurov.load_scenario(SCENARIO_DIR / "paper_fig3.toml")
    return s.replace(duration=20.0, refused_step_policy=policy)


class FailsAt:
    """A PD law in numpy that misbehaves in 5 <= t < 7 in a chosen way."""

    def __init__(self, how: str) -> None:
        self.how = how

    def step(self, eta: Any, nu: Any, eta_d: Any, eta_d_dot: Any, eta_d_ddot: Any, t: float = 0.0) -> Any:
        if 5.0 <= t < 7.0:
            if self.how == "raise":
                raise RuntimeError("boom")
            if self.how == "shape":
                return np.zeros(5)
            if self.how == "str":
                return "thrust"
            if self.how == "nan":
                return np.array([0, 0, np.nan, 0, 0, 0])
            if self.how == "inf":
                return np.array([np.inf, 0, 0, 0, 0, 0])
        return 100.0 * (np.asarray(eta_d) - eta) + 1.0


@pytest.mark.parametrize(
    ("how", "status"),
    [
        ("raise", "invalid_argument"),
        ("shape", "invalid_argument"),
        ("str", "invalid_argument"),
        ("nan", "non_finite_output"),
        ("inf", "non_finite_output"),
    ],
)
@pytest.mark.parametrize("policy", ["zero", "hold"])
def test_a_failing_controller_is_a_refused_step_and_the_run_goes_on(how: str, status: str, policy: str) -> None:
    scenario = quiet_scenario(policy)
    with pytest.warns(neurov.RefusedStepsWarning, match=f"10 of 101 steps refused, the first at t = 5 s \\({status}"):
        result = neurov.simulate(scenario, FailsAt(how))
    rows = round(scenario.duration / scenario.dt) + 1
    assert len(result.t) == rows and not result.diverged
    bad = (result.t >= 5.0 - 1e-9) & (result.t < 7.0 - 1e-9)
    assert np.count_nonzero(bad) == 10
    np.testing.assert_array_equal(result.controller_status[bad], int(getattr(_core.Status, status)))
    np.testing.assert_array_equal(result.controller_status[~bad], 0)
    last_good = np.flatnonzero(bad)[0] - 1
    held = np.zeros(6) if policy == "zero" else result.tau_demanded[last_good]
    np.testing.assert_array_equal(result.tau_demanded[bad], np.broadcast_to(held, (10, 6)))
    assert result.metrics(after=0.0)["refused_steps"] == 10
    errors = result.extra["controller_errors"]
    assert list(errors) == [status] and errors[status]["count"] == 10
    assert errors[status]["first_t"] == pytest.approx(5.0)


def test_a_raising_controller_message_is_kept() -> None:
    with pytest.warns(neurov.RefusedStepsWarning):
        result = neurov.simulate(quiet_scenario(), FailsAt("raise"))
    assert result.extra["controller_errors"]["invalid_argument"]["first"] == "step raised RuntimeError: boom"
    assert result.first_refusal == "t = 5 s, invalid_argument: step raised RuntimeError: boom"


class WrongSignature:
    """A step that takes the pose only: every call raises TypeError."""

    def step(self, eta: Any) -> Any:
        return -eta


def test_a_controller_refused_at_every_step_is_counted_over_the_run_and_warned() -> None:
    scenario = quiet_scenario()  # 101 rows, 51 of them in the window t >= 10 s
    with pytest.warns(neurov.RefusedStepsWarning, match="'WrongSignature': 101 of 101 steps refused"):
        result = neurov.simulate(scenario, WrongSignature())
    m = result.metrics()
    assert m["refused_steps"] == 101 and m["refused_steps_in_window"] == 51
    assert result.first_refusal.startswith("t = 0 s, invalid_argument: step raised TypeError: ")
    assert "positional argument" in result.first_refusal


class RaisingArray:
    """What a tensor of another library may do when numpy converts it."""

    def __array__(self, dtype: Any = None, copy: Any = None) -> Any:
        raise RuntimeError("tensor on another device")


@pytest.mark.parametrize(
    "tau",
    [["1"] * 6, [True] * 6, np.ones(6, dtype=complex), np.ones(6, dtype=object), "thrust", {"X": 1.0},
     RaisingArray()],
    ids=["numeric strings", "bools", "complex", "object array", "str", "dict", "raising __array__"],
)
def test_values_that_are_not_real_numbers_are_refused_as_simulator_step_refuses_them(tau: Any) -> None:
    scenario = quiet_scenario().replace(duration=2.0)
    sim = neurov.Simulator(scenario)
    sim.reset()
    with pytest.raises(TypeError, match="argument 'tau' must"):
        sim.step(tau)

    class Returns:
        def step(self, *args: Any) -> Any:
            return tau

    with pytest.warns(neurov.RefusedStepsWarning, match="11 of 11 steps refused"):
        result = neurov.simulate(scenario, Returns())
    np.testing.assert_array_equal(result.controller_status, int(_core.Status.invalid_argument))
    assert "not six real numbers" in result.first_refusal


def test_an_object_without_step_is_a_named_error() -> None:
    with pytest.raises(TypeError, match="argument 'controller' must be .* step"):
        neurov.simulate(quiet_scenario(), object())


# ----------------------------------------------------------- the simulator by hand


def test_the_simulator_stepped_by_hand_is_simulate() -> None:
    scenario = quiet_scenario()
    sim = neurov.Simulator(scenario)
    obs = sim.reset()
    assert isinstance(obs, neurov.Observation) and obs.t == 0.0
    with pytest.raises(dataclasses.FrozenInstanceError):
        obs.t = 1.0  # type: ignore[misc]
    law = FailsAt("none")
    while not sim.done:
        obs = sim.step(law.step(obs.eta, obs.nu, obs.eta_d, obs.eta_d_dot, obs.eta_d_ddot, t=obs.t))
    by_hand = sim.result()
    expected = neurov.simulate(scenario, FailsAt("none"))
    np.testing.assert_array_equal(by_hand.eta, expected.eta)
    np.testing.assert_array_equal(by_hand.tau_demanded, expected.tau_demanded)
    assert by_hand.metrics() == expected.metrics()
    eta, nu = sim.state
    assert eta.shape == nu.shape == (6,)
    assert sim.steps == len(expected.t) and sim.done and not sim.diverged


def test_reset_gives_the_same_run_again() -> None:
    scenario = quiet_scenario().replace(noise_eta=np.full(6, 0.01))
    sim = neurov.Simulator(scenario)
    first = sim.run(FailsAt("none")).eta
    sim.reset()
    np.testing.assert_array_equal(sim.run(FailsAt("none")).eta, first)
    sim.reset(seed=7)
    assert not np.array_equal(sim.run(FailsAt("none")).eta, first)


@pytest.mark.parametrize(
    ("tau", "error"),
    [(np.zeros(5), ValueError), ([0, 0, np.nan, 0, 0, 0], ValueError), ([np.inf] * 6, ValueError),
     ("x", TypeError), (None, TypeError)],
)
def test_a_bad_tau_names_tau_and_loses_nothing(tau: Any, error: type[Exception]) -> None:
    sim = neurov.Simulator(quiet_scenario())
    sim.reset()
    sim.step(np.ones(6))
    before, (eta, nu) = sim.result(), sim.state
    with pytest.raises(error, match="'tau'"):
        sim.step(tau)
    assert sim.steps == 1
    np.testing.assert_array_equal(sim.result().eta, before.eta)
    np.testing.assert_array_equal(sim.state[0], eta)
    np.testing.assert_array_equal(sim.state[1], nu)
    sim.step(np.ones(6))
    assert sim.steps == 2


def test_step_after_done_is_an_error_and_keeps_the_rows() -> None:
    scenario = quiet_scenario().replace(duration=1.0)
    sim = neurov.Simulator(scenario)
    sim.reset()
    while not sim.done:
        sim.step(np.zeros(6))
    with pytest.raises(RuntimeError, match="run is done"):
        sim.step(np.zeros(6))
    assert len(sim.result().t) == 6


def test_the_simulator_refuses_a_non_scenario() -> None:
    with pytest.raises(TypeError, match="argument 'scenario'"):
        neurov.Simulator(SCENARIO_DIR / "paper_fig3.toml")  # type: ignore[arg-type]


def test_config_of_the_simulator_is_the_scenarios() -> None:
    scenario = quiet_scenario()
    assert repr(neurov.Simulator(scenario)._sim.config) == repr(simulation_config(scenario))
