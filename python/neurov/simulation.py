"""Run a scenario: build the vehicle and controller, run the closed loop in C++,
and wrap the arrays in a :class:`Result` with metrics and export."""

from __future__ import annotations

import csv
import json
from collections.abc import Iterable, Iterator, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from neurov import _core
from neurov.scenario import ControllerSpec, Scenario, make_centres
from neurov.vehicle_file import load_thrusters, load_vehicle_parameters

__all__ = [
    "Result", "build_controller", "build_vehicle", "default_centre_box", "simulate", "simulate_many",
    "simulation_config",
]

Array = NDArray[np.float64]

_SERIES = (
    "t", "eta", "nu", "eta_d", "eta_d_dot", "tau_demanded", "tau_applied", "disturbance", "s",
    "thrusts", "theta", "adaptive_norm", "controller_status", "plant_status", "faults",
)


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
    poses = np.vstack([poses, scenario.eta0])
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


@dataclass
class Result:
    """Time series of one closed-loop run; rows at t_k = k dt."""

    scenario: Scenario
    controller: str
    t: Array
    eta: Array
    nu: Array
    eta_d: Array
    eta_d_dot: Array
    tau_demanded: Array
    tau_applied: Array
    disturbance: Array
    s: Array
    thrusts: Array
    theta: Array
    adaptive_norm: Array
    controller_status: NDArray[np.uint8]
    plant_status: NDArray[np.uint8]
    faults: NDArray[np.uint8]
    diverged: bool
    wall_time: float = 0.0
    extra: dict[str, Any] = field(default_factory=dict)

    @property
    def error(self) -> Array:
        """eta - eta_d, shape (K, 6)."""
        return self.eta - self.eta_d

    def metrics(self, after: float = 0.0) -> dict[str, Any]:
        """Tracking and effort metrics over t >= after (a transient to skip):
        RMS error per DOF and of the 3-D position, maximum errors, mean and
        maximum |tau| per DOF, control energy integral ||tau|| dt, integral
        absolute error per DOF. Non-finite or diverged runs give inf errors."""
        m = self.t >= after
        if not np.any(m):
            raise ValueError(f"argument 'after' = {after} leaves no samples (run ends at {self.t[-1] if len(self.t) else 0})")
        e = self.error[m]
        tau = self.tau_demanded[m]
        dt = self.scenario.dt
        pos = np.linalg.norm(e[:, :3], axis=1)
        names = ("x", "y", "z", "roll", "pitch", "yaw")
        out: dict[str, Any] = {
            "rmse_position_m": float(np.sqrt(np.mean(pos**2))),
            "max_position_error_m": float(np.max(pos)),
            "rmse_yaw_rad": float(np.sqrt(np.mean(e[:, 5] ** 2))),
            "max_yaw_error_rad": float(np.max(np.abs(e[:, 5]))),
            "rmse": {n: float(np.sqrt(np.mean(e[:, i] ** 2))) for i, n in enumerate(names)},
            "max_abs_error": {n: float(np.max(np.abs(e[:, i]))) for i, n in enumerate(names)},
            "iae": {n: float(np.sum(np.abs(e[:, i])) * dt) for i, n in enumerate(names)},
            "mean_abs_tau": float(np.mean(np.abs(tau))),
            "max_abs_tau": float(np.max(np.abs(tau))),
            "mean_abs_tau_dof": [float(x) for x in np.mean(np.abs(tau), axis=0)],
            "max_abs_tau_dof": [float(x) for x in np.max(np.abs(tau), axis=0)],
            "control_energy": float(np.sum(np.linalg.norm(tau, axis=1)) * dt),
            "final_adaptive_norm": float(self.adaptive_norm[-1]),
            "max_adaptive_norm": float(np.max(self.adaptive_norm)),
            "refused_steps": int(np.count_nonzero(self.controller_status[m])),
            "diverged": bool(self.diverged),
        }
        if self.diverged or not np.all(np.isfinite(e)):
            for k in ("rmse_position_m", "max_position_error_m", "rmse_yaw_rad", "max_yaw_error_rad"):
                out[k] = float("inf")
        return out

    def columns(self) -> dict[str, Array]:
        """Flat named columns (one per DOF, thruster and parameter)."""
        cols: dict[str, Array] = {"t": self.t}
        dof = ("x", "y", "z", "phi", "theta", "psi")
        body = ("u", "v", "w", "p", "q", "r")
        for name, arr, labels in (
            ("eta", self.eta, dof), ("nu", self.nu, body), ("eta_d", self.eta_d, dof),
            ("eta_d_dot", self.eta_d_dot, dof), ("tau_demanded", self.tau_demanded, body),
            ("tau_applied", self.tau_applied, body), ("disturbance", self.disturbance, body),
            ("s", self.s, dof),
        ):
            for i, lab in enumerate(labels):
                cols[f"{name}_{lab}"] = arr[:, i]
        for i in range(self.thrusts.shape[1]):
            cols[f"thrust_{i}"] = self.thrusts[:, i]
        for i, n in enumerate(_core.THETA_NAMES[: self.theta.shape[1]]):
            cols[f"theta[{n}]"] = self.theta[:, i]
        cols["adaptive_norm"] = self.adaptive_norm
        cols["controller_status"] = self.controller_status.astype(np.float64)
        cols["plant_status"] = self.plant_status.astype(np.float64)
        cols["faults"] = self.faults.astype(np.float64)
        return cols

    def to_csv(self, path: str | Path) -> Path:
        """Writes every column to a CSV file with a header row."""
        path = Path(path)
        cols = self.columns()
        with path.open("w", newline="") as f:
            w = csv.writer(f)
            w.writerow(cols.keys())
            w.writerows(zip(*(c.tolist() for c in cols.values())))
        return path

    def to_npz(self, path: str | Path) -> Path:
        """Writes the arrays (and the scenario name and controller) to .npz."""
        path = Path(path)
        arrays = {k: getattr(self, k) for k in _SERIES}
        np.savez_compressed(path, scenario=self.scenario.name, controller=self.controller,
                            diverged=self.diverged, **arrays)
        return path

    def summary_json(self, after: float = 0.0) -> str:
        return json.dumps({"scenario": self.scenario.name, "controller": self.controller,
                           **self.metrics(after)}, indent=2)


def simulate(scenario: Scenario, controller: ControllerSpec | None = None, *,
             vehicle: _core.Vehicle | None = None) -> Result:
    """Runs one closed loop (the loop itself is C++; no Python per step)."""
    import time

    spec = controller or scenario.controller
    plant = vehicle if vehicle is not None else build_vehicle(scenario)
    ctrl = build_controller(spec, scenario)
    config = simulation_config(scenario)
    start = time.perf_counter()
    raw = _core.run_closed_loop(plant, ctrl, config)
    wall = time.perf_counter() - start
    diverged = bool(raw.pop("diverged"))
    return Result(scenario=scenario, controller=spec.name, diverged=diverged, wall_time=wall, **raw)


def simulate_many(runs: Sequence[tuple[Scenario, ControllerSpec | None]] | Iterable[tuple[Scenario, ControllerSpec | None]],
                  progress: bool = False) -> Iterator[Result]:
    """Runs several scenarios one after another, with a progress bar on
    stderr when `progress` (the bar is plain text; no extra dependency)."""
    runs = list(runs)
    bar = _Progress(len(runs)) if progress else None
    for scenario, spec in runs:
        yield simulate(scenario, spec)
        if bar:
            bar.advance()
    if bar:
        bar.close()


class _Progress:
    """A minimal text progress bar on stderr."""

    def __init__(self, total: int) -> None:
        import sys

        self.total = max(total, 1)
        self.done = 0
        self.stream = sys.stderr

    def advance(self, n: int = 1) -> None:
        self.done += n
        width = 30
        filled = int(width * self.done / self.total)
        self.stream.write(f"\r[{'#' * filled}{'.' * (width - filled)}] {self.done}/{self.total}")
        self.stream.flush()

    def close(self) -> None:
        self.stream.write("\n")
        self.stream.flush()
