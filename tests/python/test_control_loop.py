"""neurov.control's discrete-time systems: a built-in controller, the
reference model and the sampled plant joined by control.interconnect and run
by control.input_output_response give neurov.simulate's rows (to 1e-9 of
each series' magnitude); python-control's repeated calls do not step a
controller twice; what the loop cannot model is refused by name."""

from __future__ import annotations

import subprocess
import sys
from importlib import resources

import numpy as np
import pytest

ct = pytest.importorskip("control", minversion="0.10")

import neurov  # noqa: E402
import neurov.control as nc  # noqa: E402
from neurov.laws.registry import REGISTRY, build_controller  # noqa: E402
from neurov.errors import ScenarioError  # noqa: E402
from neurov.config.scenario import ControllerSpec, Scenario  # noqa: E402

PD_GAINS = {"kp": [100, 100, 100, 25, 25, 25], "kd": [200, 200, 200, 50, 50, 50]}


def shipped(name: str, **changes: object) -> Scenario:
    return neurov.load_scenario(resources.files("neurov") / "scenarios" / f"{name}.toml").replace(**changes)


def relative_difference(response: ct.TimeResponseData, result: neurov.Result) -> dict[str, float]:
    """max |a - b| / max |b| per series, b neurov.simulate's."""
    y = response.outputs
    series = {"eta": (y[:6], result.eta), "nu": (y[6:12], result.nu), "tau": (y[12:18], result.tau_demanded),
              "eta_d": (y[18:24], result.eta_d), "eta_d_dot": (y[24:30], result.eta_d_dot)}
    out = {}
    for key, (ours, theirs) in series.items():
        assert ours.T.shape == theirs.shape, key
        scale = np.max(np.abs(theirs))
        assert scale > 0, f"{key} is zero throughout: the comparison would prove nothing"
        out[key] = float(np.max(np.abs(ours.T - theirs)) / scale)
    return out


def test_paper_nn_controller_on_paper_fig3_is_neurov_simulate() -> None:
    # The paper's controller on its Fig. 3 path, without thrusters (the loop
    # has none); 12 s: the depth change and the first metres of the square.
    scenario = shipped("paper_fig3", duration=12.0, use_thrusters=False)
    response = nc.simulate(scenario)
    result = neurov.simulate(scenario)
    assert np.array_equal(response.time, result.t)
    assert result.adaptive_norm[-1] > 0.1  # the weights moved: the NN state is carried
    assert max(relative_difference(response, result).values()) <= 1e-9


def test_pd_on_a_helix_in_a_current_is_neurov_simulate() -> None:
    scenario = shipped("nerov_helix", duration=20.0, use_thrusters=False, current=[0.1, -0.05, 0.0],
                       eta0=[0.5, 0.0, 0.2, 0.0, 0.0, 0.1], nu0=[0.05, 0.0, 0.0, 0.0, 0.0, 0.0])
    spec = ControllerSpec("pd", **PD_GAINS)
    response = nc.simulate(scenario, spec)
    result = neurov.simulate(scenario, spec)
    assert max(relative_difference(response, result).values()) <= 1e-9


@pytest.mark.parametrize("kind", sorted(REGISTRY))
def test_every_built_in_controller_carries_its_memory(kind: str) -> None:
    # Each controller type's state layout: the loop of a few steps is
    # neurov.simulate's for every registered type.
    fields = dict(PD_GAINS, ki=[5.0] * 6) if kind == "pid" else PD_GAINS if kind == "pd" else {}
    scenario = shipped("paper_fig3", duration=3.0, use_thrusters=False)
    spec = ControllerSpec(kind, **fields)
    response = nc.simulate(scenario, spec)
    result = neurov.simulate(scenario, spec)
    y = response.outputs
    assert np.allclose(y[:6].T, result.eta, rtol=0, atol=1e-9 * np.max(np.abs(result.eta)))
    assert np.allclose(y[12:18].T, result.tau_demanded, rtol=0, atol=1e-9 * np.max(np.abs(result.tau_demanded)))


def test_a_controller_of_unknown_layout_carries_its_whole_snapshot(monkeypatch: pytest.MonkeyPatch) -> None:
    # A built-in controller the layout table does not name (one added later)
    # carries every numeric field of its snapshot: the NN run that way is
    # still neurov.simulate's.
    from neurov.control import sampled

    monkeypatch.delitem(sampled._MEMORY, "NNAdaptiveController")
    scenario = shipped("paper_fig3", duration=4.0, use_thrusters=False)
    reference, controller, plant = nc.scenario_systems(scenario)
    assert controller.nstates > 64 * 24 + 6 * 64  # the centres and the weights, at least
    assert max(relative_difference(nc.simulate(scenario), neurov.simulate(scenario)).values()) <= 1e-9


def test_repeated_calls_step_the_controller_once() -> None:
    scenario = shipped("paper_fig3", duration=3.0, use_thrusters=False)
    controller = build_controller(scenario.controller, scenario)
    weights = controller.weights.copy()
    system = nc.controller_system(controller, scenario.dt)
    rng = np.random.default_rng(3)
    u = np.concatenate([rng.normal(0, 0.3, 12), [1.0, 0.5, 2.0, 0.0, 0.0, 0.3], np.zeros(12)])
    x0 = system.x0
    first = system.dynamics(0.0, x0, u), system.output(0.0, x0, u)
    other = system.dynamics(0.0, x0, u * 0.5)
    again = system.dynamics(0.0, x0, u), system.output(0.0, x0, u)
    assert np.array_equal(first[0], again[0]) and np.array_equal(first[1], again[1])
    assert not np.array_equal(first[0], other)
    assert not np.array_equal(first[0], x0)  # the weights moved...
    assert np.array_equal(controller.weights, weights)  # ...in the system's state, not in the object
    expected = controller.step(u[:6], u[6:12], u[12:18], u[18:24], u[24:30])
    assert np.array_equal(first[1], expected)


def test_the_loop_is_an_interconnection_of_the_three_systems() -> None:
    scenario = shipped("paper_fig3", duration=1.0, use_thrusters=False)
    reference, controller, plant = nc.scenario_systems(scenario)
    assert all(s.isdtime(strict=True) and s.dt == scenario.dt for s in (reference, controller, plant))
    assert plant.ninputs == 6 and plant.nstates == 12 and controller.ninputs == 30
    loop = ct.interconnect([reference, controller, plant], inputs=list(nc.COMMAND_NAMES),
                           outputs=list(nc.STATE_NAMES))
    t = nc.time_grid(scenario)
    response = ct.input_output_response(loop, t, nc.command_input(scenario, t), X0=nc.initial_state(loop))
    result = neurov.simulate(scenario)
    assert np.allclose(response.outputs[:6].T, result.eta, rtol=0, atol=1e-9 * np.max(np.abs(result.eta)))
    assert np.allclose(response.outputs[6:].T, result.nu, rtol=0, atol=1e-9 * np.max(np.abs(result.nu)))


@pytest.mark.parametrize("duration", [2.5, 0.5])
def test_time_grid_is_the_runs_rows(duration: float) -> None:
    # 12.5 and 2.5 periods: the C++ rounds half away from zero, Python's round() to even.
    scenario = shipped("paper_fig3", duration=duration, use_thrusters=False)
    assert np.array_equal(nc.time_grid(scenario), neurov.simulate(scenario).t)


def test_unmodelled_features_are_named() -> None:
    with pytest.raises(ScenarioError, match=r"argument 'scenario' \('paper_fig3'\).*thrusters \(use_thrusters"):
        nc.closed_loop(shipped("paper_fig3"))
    with pytest.raises(ValueError, match=r"thrusters.*disturbances"):
        nc.simulate(shipped("paper_fig5"))
    with pytest.raises(ValueError, match=r"sensors"):
        nc.scenario_systems(shipped("nerov_depth_step_realistic", use_thrusters=False))
    for changes, named in [({"noise_eta": [0.01] * 6}, "noise_eta"), ({"control_delay": 1}, "control_delay"),
                           ({"current_steps": [neurov._core.CurrentStep(time=1.0, velocity=[0.1, 0, 0])]},
                            "current_steps")]:
        with pytest.raises(ValueError, match=named):
            nc.closed_loop(shipped("paper_fig3", use_thrusters=False, **changes))
    with pytest.raises(TypeError, match="argument 'scenario'"):
        nc.closed_loop("paper_fig3")


def test_bad_arguments_name_themselves() -> None:
    scenario = shipped("paper_fig3", duration=1.0, use_thrusters=False)
    nn = build_controller(scenario.controller, scenario)
    with pytest.raises(ValueError, match=r"argument 'dt' \(0.1 s\) must be the controller's control period.*0.2"):
        nc.controller_system(nn, 0.1)
    for dt in (0.0, -0.2, float("nan"), float("inf")):
        with pytest.raises(ValueError, match="argument 'dt'"):
            nc.sampled_plant(neurov.Vehicle.nerov(), dt)
    with pytest.raises(TypeError, match="argument 'dt'"):
        nc.controller_system(neurov.PDController(np.ones(6), np.ones(6)), "0.2")

    class Mine:
        def step(self, eta, nu, eta_d, eta_d_dot, eta_d_ddot):  # type: ignore[no-untyped-def]
            return np.zeros(6)

    with pytest.raises(TypeError, match="argument 'controller' must be a built-in controller"):
        nc.controller_system(Mine(), 0.2)
    with pytest.raises(TypeError, match="argument 'reference'"):
        nc.reference_system(nn, 0.2)
    with pytest.raises(ValueError, match="argument 'substeps'"):
        nc.sampled_plant(neurov.Vehicle.nerov(), 0.2, substeps=0)
    with pytest.raises(ValueError, match="current"):
        nc.sampled_plant(neurov.Vehicle.nerov(), 0.2, current=[0.1, 0.0])
    with pytest.raises(ValueError, match="argument 'x0'"):
        nc.sampled_plant(neurov.Vehicle.nerov(), 0.2, x0=np.zeros(6))
    with pytest.raises(TypeError, match="argument 'vehicle'"):
        nc.sampled_plant(nn, 0.2)
    with pytest.raises(ValueError, match=r"argument 'system'.*\['foreign'\]"):
        nc.initial_state(ct.nlsys(lambda t, x, u, p: x, None, states=1, inputs=1, outputs=1, dt=0.2,
                                  name="foreign"))


def test_a_refused_step_is_an_error_not_a_silent_force() -> None:
    system = nc.controller_system(neurov.PDController(np.ones(6), np.ones(6)), 0.2)
    u = np.zeros(30)
    u[0] = np.nan
    with pytest.raises(ValueError, match=r"^controller: .*argument 'eta'"):
        system.output(0.0, system.x0, u)


def test_import_neurov_does_not_import_control() -> None:
    code = "import sys, neurov; assert 'control' not in sys.modules, 'python-control was imported'"
    subprocess.run([sys.executable, "-c", code], check=True)
