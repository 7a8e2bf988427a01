"""Run a scenario: build the vehicle and controller, run the closed loop in C++,
and wrap the arrays in a :class:`Result` with metrics and export."""

from __future__ import annotations

from collections.abc import Iterable, Iterator, Sequence
from typing import Any

import numpy as np
from numpy.typing import NDArray

from neurov import _core
from neurov.result import Result
from neurov.scenario import ControllerSpec, Scenario, make_centres
from neurov.vehicle_file import load_thrusters, load_vehicle_parameters

__all__ = [
    "Result", "build_controller", "build_vehicle", "default_centre_box", "simulate", "simulate_many",
    "simulation_config",
]

Array = NDArray[np.float64]


def build_vehicle(scenario: Scenario) -> _core.Vehicle:
    """The scenario's vehicle, with its parameter overrides applied."""
    params = load_vehicle_parameters(scenario.vehicle_path())
    params.update(scenario.vehicle_parameters or {})
    return _core.Vehicle(**params)


def _member(enum: Any, value: str, field: str) -> Any:
    """The member of a bound C++ enum named `value`; ValueError naming the field."""
    try:
        return enum.__members__[value]
    except KeyError:
        raise ValueError(f"{field} must be one of {', '.join(map(repr, enum.__members__))}, got {value!r}") from None


def simulation_config(scenario: Scenario) -> _core.SimulationConfig:
    """The scenario as the C++ SimulationConfig a run takes (the thruster
    layout from the vehicle file's [thrusters])."""
    c = _core.SimulationConfig()
    c.dt = scenario.dt
    c.substeps = scenario.substeps
    c.duration = scenario.duration
    c.eta0 = scenario.eta0
    c.nu0 = scenario.nu0
    times, poses = scenario.command.timed_poses()
    if scenario.command.interpolation not in ("linear", "hold"):
        raise ValueError(f"command.interpolation must be 'linear' or 'hold', got {scenario.command.interpolation!r}")
    c.command = _core.Command(times=times, poses=poses, linear=scenario.command.interpolation == "linear")
    c.lambda_d = scenario.lambda_d
    c.omega = scenario.omega
    c.disturbances = [_core.SinusoidalDisturbance(**vars(d)) for d in scenario.disturbances]
    c.current = scenario.current
    c.current_amplitude = scenario.current_amplitude
    c.current_period = scenario.current_period
    c.noise_eta = scenario.noise_eta
    c.noise_nu = scenario.noise_nu
    c.seed = scenario.seed
    c.sensor_faults = [
        _core.SensorFault(**{**vars(f), "kind": _member(_core.SensorFaultKind, f.kind, "sensor_faults.kind")})
        for f in scenario.sensor_faults
    ]
    c.current_steps = [_core.CurrentStep(**vars(s)) for s in scenario.current_steps]
    c.refused_step_policy = _member(_core.RefusedStepPolicy, scenario.refused_step_policy, "refused_step_policy")
    if scenario.use_thrusters:
        t = load_thrusters(scenario.vehicle_path())
        if t is None:
            raise ValueError(f"scenario {scenario.name!r}: vehicle file {scenario.vehicle_path()} has no [thrusters] table")
        c.use_thrusters = True
        c.thrusters = _core.ThrusterConfig(
            matrix=t["matrix"], max_thrust=t["max_thrust"], min_thrust=t["min_thrust"],
            saturation=_member(_core.Saturation, scenario.saturation, "saturation"),
            time_constant=(t["time_constant"] if scenario.thruster_time_constant is None
                           else scenario.thruster_time_constant),
        )
        c.failures = [_core.ThrusterFailure(**vars(f)) for f in scenario.thruster_failures]
    return c


def default_centre_box(scenario: Scenario) -> tuple[Array, Array]:
    """The box the NN centres fill when the scenario gives none: the commanded
    poses' bounding box padded by 2 m and 0.5 rad for eta; +-1 m/s and
    +-0.5 rad/s for the velocities nu and nu_r; +-0.5 m/s^2 and +-0.5 rad/s^2
    for nu_r_dot. A written-down choice: the paper says only "uniformly spaced
    in the state space"."""
    _, poses = scenario.command.timed_poses()
    # The box is the first use of eta0 and the poses: a NaN in either would
    # otherwise be reported as the box's ('low' and 'high' must be finite).
    eta0 = np.asarray(scenario.eta0, dtype=np.float64)
    if eta0.shape != (6,) or not np.all(np.isfinite(eta0)):
        raise ValueError(f"scenario {scenario.name!r}: argument 'eta0' (the initial pose) must be "
                         f"6 finite numbers, got {eta0.tolist()}")
    if not np.all(np.isfinite(poses)):
        raise ValueError(f"scenario {scenario.name!r}: the command's poses must be finite, "
                         f"got a non-finite value in pose {int(np.argmin(np.all(np.isfinite(poses), axis=1)))}")
    poses = np.vstack([poses, eta0])
    pad = np.array([2.0, 2.0, 2.0, 0.5, 0.5, 0.5])
    vel = np.array([1.0, 1.0, 1.0, 0.5, 0.5, 0.5])
    acc = np.full(6, 0.5)
    low = np.concatenate([-acc, -vel, -vel, poses.min(axis=0) - pad])
    high = np.concatenate([acc, vel, vel, poses.max(axis=0) + pad])
    return low, high


def build_controller(spec: ControllerSpec, scenario: Scenario) -> Any:
    """A fresh controller from its spec. The NN centres fill the scenario's
    box; the linear controller's theta0 'true' is the nominal vehicle's theta
    (the vehicle file without the scenario's parameter overrides: a controller
    is designed for the vehicle as documented, not the plant as perturbed)."""
    if spec.type == "nn":
        low, high = default_centre_box(scenario)
        net = _core.RbfNetwork(make_centres(spec, low, high), spec.width)
        return _core.NNAdaptiveController(
            net, spec.lambda_, spec.kd, float(spec.gamma), scenario.dt,
            modification=spec.modification, sigma_m=spec.sigma_m, kappa=spec.kappa,
            w_max=spec.w_max, dead_zone=spec.dead_zone,
        )
    if spec.type == "linear":
        theta0 = np.zeros(len(_core.THETA_NAMES))
        if spec.theta0 in ("true", "scaled"):
            nominal = _core.Vehicle(**load_vehicle_parameters(scenario.vehicle_path()))
            theta0 = _core.regressor_parameters(nominal)
            if spec.theta0 == "scaled":
                theta0 = theta0 * spec.theta0_scale
        return _core.LinearAdaptiveController(spec.lambda_, spec.kd, spec.gamma, scenario.dt, theta0)
    if spec.type == "pd":
        return _core.PDController(spec.kp, spec.kd)
    if spec.type == "pid":
        return _core.PIDController(spec.kp, spec.ki, spec.kd, spec.integral_limit, scenario.dt)
    if spec.type == "smc":
        nominal = _core.Vehicle(**load_vehicle_parameters(scenario.vehicle_path()))
        return _core.SlidingModeController(spec.lambda_, spec.kd, spec.k, spec.phi,
                                           _core.regressor_parameters(nominal))
    raise ValueError(f"controller.type must be 'nn', 'linear', 'pd', 'pid' or 'smc', got {spec.type!r}")


def simulate(scenario: Scenario, controller: ControllerSpec | Any = None, *,
             vehicle: _core.Vehicle | None = None, label: str | None = None) -> Result:
    """Runs one closed loop. `controller` is a :class:`ControllerSpec` (None:
    the scenario's), a built-in controller object (``neurov.PDController(kp,
    kd)``, ...: the loop runs in C++, no Python per step), or any object
    following :class:`neurov.Controller` (stepped from Python through
    :class:`neurov.Simulator`; its refused steps are logged and the run goes
    on; its ``reset()``, if any, is called first). A built-in object runs
    from the state it is in (e.g. warm-started weights). `label` names the
    controller in the result (default: the spec's name, the class name of
    an object)."""
    import time

    from neurov.controller import is_built_in, require_controller

    plant = vehicle if vehicle is not None else build_vehicle(scenario)
    if controller is None or isinstance(controller, ControllerSpec):
        spec = controller or scenario.controller
        ctrl, name = build_controller(spec, scenario), spec.name
    else:
        require_controller(controller)
        ctrl, name = controller, type(controller).__name__
        if not is_built_in(ctrl):
            from neurov.simulator import Simulator

            return Simulator(scenario, vehicle=plant, label=label or name).run(ctrl)
    config = simulation_config(scenario)
    start = time.perf_counter()
    raw = _core.run_closed_loop(plant, ctrl, config)
    wall = time.perf_counter() - start
    diverged = bool(raw.pop("diverged"))
    return Result(scenario=scenario, controller=label or name, diverged=diverged, wall_time=wall, **raw)


def simulate_many(runs: Sequence[tuple[Scenario, ControllerSpec | None]] | Iterable[tuple[Scenario, ControllerSpec | None]],
                  progress: bool = False) -> Iterator[Result]:
    """Runs several scenarios one after another; with `progress`, a progress
    bar on stderr while stderr is a terminal (see :mod:`neurov.progress`)."""
    from neurov.progress import progress_bar

    runs = list(runs)
    with progress_bar(len(runs), "runs", quiet=not progress) as bar:
        for scenario, spec in runs:
            yield simulate(scenario, spec)
            bar.update(1)
