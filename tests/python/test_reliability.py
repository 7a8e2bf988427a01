"""Bad configuration through the Python API, where test_bad_input.py (array
and scalar arguments) and the file tests (test_vehicle_files.py,
test_scenario.py) leave gaps: centre sets, widths, gains and time steps of
every controller, the closed loop's configuration and the fault tables of
a scenario file. Each error must be a ValueError or TypeError that names the
offending field. docs/reliability.md lists what is covered where.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any, Callable

import numpy as np
import pytest

import neurov
from neurov import _core
from neurov.config.reading import load_scenario
from neurov.config.scenario import ScenarioError

CENTRES = np.random.default_rng(1).uniform(-1, 1, size=(4, 24))
LAM = np.full(6, 0.5)
KD = np.full(6, 100.0)


# ----------------------------------------------------------- RBF network


@pytest.mark.parametrize(
    ("centres", "width", "extra", "field"),
    [
        pytest.param(np.zeros((0, 24)), 1.0, {}, "centres", id="empty centre set"),
        pytest.param(np.zeros((3, 0)), 1.0, {}, "centres", id="centres without inputs"),
        pytest.param(CENTRES, [1.0, 1.0, 1.0], {}, "width", id="fewer widths than centres"),
        pytest.param(CENTRES, [1.0] * 5, {}, "width", id="more widths than centres"),
        pytest.param(CENTRES, 0.0, {}, "widths", id="zero width"),
        pytest.param(CENTRES, -30.0, {}, "widths", id="negative width"),
        pytest.param(CENTRES, [1.0, 1.0, -1.0, 1.0], {}, "widths", id="one negative width"),
        pytest.param(CENTRES, 1e-200, {}, "overflows", id="width whose 1/(2 sigma^2) overflows"),
        pytest.param(CENTRES, np.nan, {}, "width", id="NaN width"),
        pytest.param(CENTRES, np.inf, {}, "width", id="infinite width"),
        pytest.param(CENTRES, 1.0, {"input_offset": np.zeros(23)}, "input_offset", id="offset of 23"),
        pytest.param(CENTRES, 1.0, {"input_scale": np.zeros(24)}, "input_scale", id="zero scale"),
        pytest.param(CENTRES, 1.0, {"input_scale": -np.ones(24)}, "input_scale", id="negative scale"),
    ],
)
def test_rbf_network_names_the_bad_field(centres: Any, width: Any, extra: dict[str, Any], field: str) -> None:
    with pytest.raises(ValueError, match=field):
        neurov.RbfNetwork(centres, width, **extra)


def test_nn_controller_needs_24_inputs() -> None:
    with pytest.raises(ValueError, match="'network' must have 24 inputs"):
        neurov.NNAdaptiveController(neurov.RbfNetwork(CENTRES[:, :6], 1.0), LAM, KD)


def test_nn_weights_whose_norm_overflows_are_refused() -> None:
    c = nn()
    before = c.weights
    with pytest.raises(ValueError, match="'weights'.*overflows"):
        c.weights = np.full((6, 4), 1e200)
    np.testing.assert_array_equal(c.weights, before)
    assert np.isfinite(c.weight_norm)


def test_jacobian_dot_of_an_overflowing_rate_is_an_error() -> None:
    with pytest.raises(ValueError, match="'nu'.*overflows"):
        neurov.jacobian_dot(np.array([0, 0, 0, 0.3, 1.4, 0.5]), np.array([0, 0, 0, 1e308, 1e308, 1e308]))


def nn(**kw: Any) -> neurov.NNAdaptiveController:
    args: dict[str, Any] = {"lambda_": LAM, "kd": KD}
    args.update(kw)
    return neurov.NNAdaptiveController(neurov.RbfNetwork(CENTRES, 1.0), **args)


# ------------------------------------------- gains and time steps, every controller

BAD_CONTROLLERS: dict[str, tuple[Callable[[], Any], str]] = {
    "NN dt = 0": (lambda: nn(dt=0.0), "dt"),
    "NN dt < 0": (lambda: nn(dt=-0.2), "dt"),
    "NN lambda = 0": (lambda: nn(lambda_=np.zeros(6)), "lambda"),
    "NN negative kd": (lambda: nn(kd=-KD), "kd"),
    "NN negative gamma": (lambda: nn(gamma=-0.3), "gamma"),
    "NN sigma with sigma_m = 0": (lambda: nn(modification="sigma"), "sigma_m"),
    "NN projection with w_max = 0": (lambda: nn(modification="projection"), "w_max"),
    "NN e-modification with kappa = 0": (lambda: nn(modification="e_modification"), "kappa"),
    "NN unknown modification": (lambda: nn(modification="leaky"), "modification"),
    "NN negative dead zone": (lambda: nn(dead_zone=-1.0), "dead_zone"),
    "NN negative learning rate": (lambda: nn(learning_rates=[0.1, -0.1, 0.1, 0.1]), "learning_rates"),
    "NN learning rates of the wrong size": (lambda: nn(learning_rates=[0.1] * 3), "learning_rates"),
    "linear dt = 0": (lambda: neurov.LinearAdaptiveController(LAM, KD, 1.0, 0.0), "dt"),
    "linear negative gamma": (lambda: neurov.LinearAdaptiveController(LAM, KD, -1.0), "gamma"),
    "linear lambda < 0": (lambda: neurov.LinearAdaptiveController(-LAM, KD, 1.0), "lambda"),
    "PD negative kp": (lambda: neurov.PDController(-KD, KD), "kp"),
    "PID dt = 0": (lambda: neurov.PIDController(KD, KD, KD, KD, 0.0), "dt"),
    "PID dt < 0": (lambda: neurov.PIDController(KD, KD, KD, KD, -0.2), "dt"),
    "PID zero integral limit": (lambda: neurov.PIDController(KD, KD, KD, np.zeros(6)), "integral_limit"),
    "PID negative ki": (lambda: neurov.PIDController(KD, -KD, KD, KD), "ki"),
    "SMC zero boundary layer": (lambda: neurov.SlidingModeController(LAM, KD, KD, np.zeros(6), np.ones(24)), "phi"),
    "SMC negative switching gain": (lambda: neurov.SlidingModeController(LAM, KD, -KD, LAM, np.ones(24)), "k"),
    "reference zero damping": (lambda: neurov.ReferenceModel(np.zeros(6), np.ones(6)), "lambda_d"),
    "reference negative stiffness": (lambda: neurov.ReferenceModel(np.ones(6), -np.ones(6)), "omega"),
    "reference starting at 90 deg pitch": (
        lambda: neurov.ReferenceModel(np.ones(6), np.ones(6), [0, 0, 0, 0, np.pi / 2, 0]), "eta0"),
}


@pytest.mark.parametrize("case", list(BAD_CONTROLLERS))
def test_controller_configuration_names_the_bad_field(case: str) -> None:
    make, field = BAD_CONTROLLERS[case]
    with pytest.raises((ValueError, TypeError), match=field):
        make()


# ------------------------------------------------- the closed loop's configuration

NEROV_B = np.vstack([np.eye(6)]).T  # any full-rank 6 x 6 layout


def loop_config() -> _core.SimulationConfig:
    return _core.SimulationConfig(duration=2.0, command=_core.Command(times=[0.0], poses=[[1, 0, 0, 0, 0, 0]]))


def fault(**changes: Any) -> _core.SensorFault:
    return _core.SensorFault(**{"kind": _core.SensorFaultKind.dropout, "start": 0.4, "end": 0.8, **changes})


def with_thrusters(c: _core.SimulationConfig, limit: Any = np.full(6, 100.0)) -> None:
    c.use_thrusters = True
    c.thrusters = _core.ThrusterConfig(matrix=NEROV_B, max_thrust=limit, min_thrust=-np.full(6, 100.0))


def thruster_failure(**changes: Any) -> Callable[[_core.SimulationConfig], None]:
    def change(c: _core.SimulationConfig) -> None:
        with_thrusters(c)
        c.thruster_failures = [_core.ThrusterFailure(**{"index": 0, "efficiency": 0.0, "time": 1.0, **changes})]
    return change


def setter(field: str, value: Any) -> Callable[[_core.SimulationConfig], None]:
    return lambda c: setattr(c, field, value)


# Each case changes a good configuration; the change itself (a field of the
# wrong type or shape) or the C++ validator (a value it refuses) must name the field.
BAD_LOOPS: dict[str, tuple[Callable[[_core.SimulationConfig], Any], type[Exception], str]] = {
    "no command": (setter("command", _core.Command()), ValueError, "command.times"),
    "command not a Command": (setter("command", [0.0]), TypeError, "SimulationConfig.command"),
    "poses for two times, one time": (lambda c: setattr(c.command, "poses", np.zeros((2, 6))), ValueError,
                                      "command.poses"),
    "poses of five columns": (lambda c: setattr(c.command, "poses", np.zeros((1, 5))), ValueError,
                              "Command.poses"),
    "times not increasing": (setter("command", _core.Command(times=[1.0, 1.0], poses=np.zeros((2, 6)))),
                             ValueError, "command.times"),
    "zero dt": (setter("dt", 0.0), ValueError, "dt"),
    "zero substeps": (setter("substeps", 0), ValueError, "substeps"),
    "float substeps": (setter("substeps", 2.5), TypeError, "substeps"),
    "too many steps": (setter("duration", 1e9), ValueError, "duration"),
    "NaN initial pose": (setter("eta0", [0, 0, np.nan, 0, 0, 0]), ValueError, "eta0"),
    "initial pose of five": (setter("eta0", np.zeros(5)), ValueError, "eta0"),
    "initial pitch at 90 deg": (setter("eta0", [0, 0, 0, 0, np.pi / 2, 0]), ValueError, "eta0"),
    "negative noise": (setter("noise_nu", -np.ones(6)), ValueError, "noise_nu"),
    "negative seed": (setter("seed", -1), ValueError, "seed"),
    "disturbance in DOF 7": (setter("disturbances", [_core.SinusoidalDisturbance(dof=7)]), ValueError, "dof"),
    "disturbance as a dict": (setter("disturbances", [{"dof": 5}]), TypeError, "disturbances"),
    "unknown sensor fault": (lambda c: fault(kind="stuck"), TypeError, "kind"),
    "sensor fault ending before it starts": (setter("sensor_faults", [fault(end=0.1)]), ValueError,
                                             "sensor_faults"),
    "sensor fault without an end": (setter("sensor_faults", [fault(end=np.nan)]), ValueError, "end"),
    "negative burst noise": (setter("sensor_faults", [fault(kind=_core.SensorFaultKind.noise_burst,
                                                            noise_nu=-np.ones(6))]), ValueError, "noise_nu"),
    "current steps out of order": (setter("current_steps", [_core.CurrentStep(time=5.0),
                                                            _core.CurrentStep(time=1.0)]),
                                   ValueError, "current_steps"),
    "current step of two components": (lambda c: _core.CurrentStep(time=1.0, velocity=np.zeros(2)), ValueError,
                                       "velocity"),
    "unknown refused-step policy": (setter("refused_step_policy", "coast"), TypeError, "refused_step_policy"),
    "unknown field": (lambda c: _core.SimulationConfig(dtt=0.1), TypeError, "dtt"),
    "failure of thruster 6 of 6": (thruster_failure(index=6), ValueError, "thruster_failures.index"),
    "efficiency above one": (thruster_failure(efficiency=1.5), ValueError, "efficiency"),
    "failure without thrusters": (setter("thruster_failures", [_core.ThrusterFailure()]), ValueError,
                                  "thruster_failures"),
    "rank-deficient thrusters": (lambda c: (with_thrusters(c), setattr(c.thrusters, "matrix",
                                                                       np.eye(6)[:, [0, 1, 2, 3, 4, 4]])),
                                 ValueError, "thrusters.matrix"),
    "thruster limits of the wrong size": (lambda c: with_thrusters(c, np.full(5, 100.0)), ValueError,
                                          "max_thrust"),
}


@pytest.mark.parametrize("case", list(BAD_LOOPS))
def test_simulation_config_names_the_bad_field(case: str) -> None:
    change, error, field = BAD_LOOPS[case]
    config = loop_config()
    with pytest.raises(error, match=field):
        change(config)
        config.validate()
    # run_closed_loop hears the same validator.
    if error is ValueError:
        with pytest.raises(ValueError, match=field):
            change(config)
            neurov.run_closed_loop(neurov.Vehicle.nerov(), neurov.PDController(KD, KD), config)


def test_a_good_loop_runs() -> None:
    """The base of the cases above is valid, so each failure is its own change."""
    config = loop_config()
    config.sensor_faults = [fault()]
    with_thrusters(config)
    config.validate()
    r = neurov.run_closed_loop(neurov.Vehicle.nerov(), neurov.PDController(KD, KD), config)
    assert not r["diverged"] and len(r["t"]) == 11
    assert np.all(np.isfinite(r["tau_applied"]))


# ------------------------------------------------- fault tables of a scenario file

SCENARIO = """
duration = 10.0
[command]
type = "square"
[controller]
type = "pd"
kp = 100.0
"""

BAD_SCENARIOS = {
    "unknown sensor fault kind": ('[[sensor_faults]]\nkind = "stuck"\nstart = 1.0\nend = 2.0\n',
                                  "sensor_faults[0].kind"),
    "sensor fault ending before it starts": ('[[sensor_faults]]\nkind = "freeze"\nstart = 3.0\nend = 2.0\n',
                                             "sensor_faults[0].end"),
    "sensor fault without start": ('[[sensor_faults]]\nkind = "freeze"\nend = 2.0\n', "sensor_faults[0].start"),
    "misspelt sensor fault field": ('[[sensor_faults]]\nkind = "dropout"\nstart = 1.0\nend = 2.0\netta = false\n',
                                    "did you mean 'eta'"),
    "string for a fault's start": ('[[sensor_faults]]\nkind = "freeze"\nstart = "1"\nend = 2.0\n',
                                   "sensor_faults[0].start"),
    "burst noise of five numbers": ('[[sensor_faults]]\nkind = "noise_burst"\nstart = 1.0\nend = 2.0\n'
                                    "noise_eta = [1, 1, 1, 1, 1]\n", "sensor_faults[0].noise_eta"),
    "sensor_faults as a table": ('[sensor_faults]\nkind = "freeze"\n', "sensor_faults"),
    "current steps out of order": ('[[current_steps]]\ntime = 5.0\nvelocity = [0, 0, 0]\n'
                                   '[[current_steps]]\ntime = 4.0\nvelocity = [0, 0, 0]\n', "current_steps[1].time"),
    "current step of two components": ('[[current_steps]]\ntime = 5.0\nvelocity = [0, 0]\n',
                                       "current_steps[0].velocity"),
    "unknown refused-step policy": ('refused_step_policy = "coast"\n', "refused_step_policy"),
    "thruster failure index as a string": ('[[thruster_failures]]\nindex = "0"\n', "thruster_failures[0].index"),
}


@pytest.mark.parametrize("case", list(BAD_SCENARIOS))
def test_scenario_fault_tables_name_the_bad_field(case: str, tmp_path: Path) -> None:
    extra, field = BAD_SCENARIOS[case]
    # Top-level keys go before the first table; fault tables after the rest.
    text = extra + SCENARIO if not extra.startswith("[") else SCENARIO + extra
    path = tmp_path / "s.toml"
    path.write_text(text)
    with pytest.raises(ScenarioError) as err:
        load_scenario(path)
    assert str(path) in str(err.value) and field in str(err.value), str(err.value)
