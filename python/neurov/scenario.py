"""Scenarios: everything one closed-loop run needs, as a dataclass or a TOML file.

A scenario file (all tables but ``[command]`` and ``[controller]`` optional)::

    name = "square"
    duration = 200.0        # s
    dt = 0.2                # control period, s (the paper: 5 Hz)
    substeps = 10           # RK4 plant steps per control period
    seed = 0                # measurement noise
    refused_step_policy = "zero"  # or "hold": the force while the controller refuses a step

    [vehicle]
    preset = "nerov"        # or: file = "my_vehicle.toml" (relative to this file)
    thrusters = true        # use the vehicle file's [thrusters] table

    [initial]
    eta = [0, 0, 0, 0, 0, 0]
    nu = [0, 0, 0, 0, 0, 0]

    [reference]             # reference model, eq. 12-13
    lambda_d = 1.0          # a number for every DOF, or 6 numbers
    omega = 0.25

    [command]
    type = "square"         # waypoints | square | lawnmower | circle | helix
    side = 10.0             # the generator's arguments (neurov.trajectories)

    [controller]
    type = "nn"             # nn | linear | pd
    lambda = 0.5
    kd = [200, 200, 200, 50, 50, 50]

    [[disturbances]]
    dof = "yaw"             # surge sway heave roll pitch yaw, or 0..5
    amplitude = 50.0        # N or N m
    frequency = 0.05        # Hz

    [current]
    velocity = [0.5, 0, 0]  # NED, m/s

    [noise]
    eta = [0.05, 0.05, 0.05, 0.005, 0.005, 0.01]
    nu = 0.01

    [[sensor_faults]]       # freeze | dropout | noise_burst over [start, end)
    kind = "dropout"
    start = 100.0
    end = 102.0

    [[current_steps]]       # the mean current from `time` on
    time = 150.0
    velocity = [0.0, 0.5, 0.0]

Every error names the file and the field (``controller.kd``) and says what was
expected.
"""

from __future__ import annotations

import dataclasses
import difflib
import math
import sys
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from neurov import centres as centre_placement
from neurov import trajectories
from neurov.files import read_text
from neurov.vehicle_file import VehicleFile, VehicleFileError, preset_path, read_vehicle_file

if sys.version_info >= (3, 11):
    import tomllib
else:  # pragma: no cover
    import tomli as tomllib

__all__ = [
    "CommandSpec",
    "ControllerSpec",
    "CurrentStep",
    "Disturbance",
    "Scenario",
    "ScenarioError",
    "SensorFault",
    "ThrusterFailure",
    "load_scenario",
]

DOF_NAMES = ("surge", "sway", "heave", "roll", "pitch", "yaw")


class ScenarioError(ValueError):
    """A scenario that cannot be used: names the file, the field and what was expected."""


# --- small checked readers ---------------------------------------------------


class _Reader:
    """Reads one table of a scenario, naming `where.field` in every error."""

    def __init__(self, table: Mapping[str, Any], where: str, origin: str) -> None:
        if not isinstance(table, Mapping):
            raise ScenarioError(f"{origin}: {where}: expected a table, got {type(table).__name__}")
        self.table = table
        self.where = where
        self.origin = origin
        # Every key asked for, present or not: finish() suggests from these.
        self.used: set[str] = set()

    def _name(self, key: str) -> str:
        return f"{self.where}.{key}" if self.where else key

    def error(self, key: str, message: str) -> ScenarioError:
        return ScenarioError(f"{self.origin}: {self._name(key)}: {message}")

    def has(self, key: str) -> bool:
        self.used.add(key)
        return key in self.table

    def raw(self, key: str, default: Any = None) -> Any:
        self.used.add(key)
        return self.table.get(key, default)

    def number(self, key: str, default: float | None = None, *, minimum: float | None = None,
               positive: bool = False) -> float:
        self.used.add(key)
        if key not in self.table:
            if default is None:
                raise self.error(key, "missing (expected a number)")
            return default
        v = self.raw(key)
        if isinstance(v, bool) or not isinstance(v, (int, float)):
            raise self.error(key, f"expected a number, got {type(v).__name__} {v!r}")
        v = float(v)
        if not math.isfinite(v):
            raise self.error(key, f"expected a finite number, got {v}")
        if positive and not v > 0:
            raise self.error(key, f"expected a number > 0, got {v}")
        if minimum is not None and v < minimum:
            raise self.error(key, f"expected a number >= {minimum}, got {v}")
        return v

    def integer(self, key: str, default: int | None = None, *, minimum: int = 0) -> int:
        self.used.add(key)
        if key not in self.table:
            if default is None:
                raise self.error(key, "missing (expected an integer)")
            return default
        v = self.raw(key)
        if isinstance(v, bool) or not isinstance(v, int):
            raise self.error(key, f"expected an integer, got {type(v).__name__} {v!r}")
        if v < minimum:
            raise self.error(key, f"expected an integer >= {minimum}, got {v}")
        return v

    def string(self, key: str, default: str | None = None, choices: Sequence[str] | None = None) -> str:
        self.used.add(key)
        if key not in self.table:
            if default is None:
                raise self.error(key, "missing (expected a string)")
            return default
        v = self.raw(key)
        if not isinstance(v, str):
            raise self.error(key, f"expected a string, got {type(v).__name__} {v!r}")
        if choices is not None and v not in choices:
            raise self.error(key, f"expected one of {list(choices)}, got {v!r}")
        return v

    def boolean(self, key: str, default: bool) -> bool:
        self.used.add(key)
        if key not in self.table:
            return default
        v = self.raw(key)
        if not isinstance(v, bool):
            raise self.error(key, f"expected true or false, got {type(v).__name__} {v!r}")
        return v

    def array(self, key: str, length: int | None, default: Any = None, *, non_negative: bool = False,
              positive: bool = False, broadcast: bool = True) -> NDArray[np.float64]:
        """A list of `length` numbers (or, with broadcast, one number for all)."""
        self.used.add(key)
        if key not in self.table:
            if default is None:
                raise self.error(key, f"missing (expected {length} numbers)")
            return np.array(default, dtype=np.float64)
        v = self.raw(key)
        want = f"{length} numbers" + (" or one number" if broadcast else "") if length else "numbers"
        if broadcast and length and isinstance(v, (int, float)) and not isinstance(v, bool):
            v = [v] * length
        if not isinstance(v, list) or any(isinstance(x, bool) or not isinstance(x, (int, float)) for x in v):
            raise self.error(key, f"expected {want}, got {type(v).__name__} {v!r}")
        a = np.asarray(v, dtype=np.float64)
        if length is not None and a.shape != (length,):
            raise self.error(key, f"expected {want}, got {len(v)}")
        if not np.all(np.isfinite(a)):
            raise self.error(key, "expected finite numbers")
        if non_negative and np.any(a < 0):
            raise self.error(key, f"expected numbers >= 0, got {v}")
        if positive and np.any(a <= 0):
            raise self.error(key, f"expected numbers > 0, got {v}")
        return a

    def table_of(self, key: str) -> _Reader:
        v = self.raw(key, {})
        return _Reader(v, self._name(key), self.origin)

    def finish(self, allowed_extra: Sequence[str] = ()) -> None:
        """Unknown keys are errors (a misspelt field must not be ignored)."""
        known = self.used | set(allowed_extra)
        for key in self.table:
            if key not in known:
                close = difflib.get_close_matches(key, sorted(known), n=1)
                hint = f"; did you mean {close[0]!r}?" if close else ""
                raise self.error(key, f"unknown field{hint}")


def _dof(reader: _Reader, key: str) -> int:
    v = reader.raw(key)
    if isinstance(v, str) and v in DOF_NAMES:
        return DOF_NAMES.index(v)
    if isinstance(v, int) and not isinstance(v, bool) and 0 <= v <= 5:
        return v
    raise reader.error(key, f"expected one of {list(DOF_NAMES)} or 0..5, got {v!r}")


# --- the scenario ----------------------------------------------------------------


@dataclass
class ControllerSpec:
    """A controller and its gains. ``type`` is ``"nn"``, ``"linear"``, ``"pd"``,
    ``"pid"`` or ``"smc"``.

    nn: ``lambda_``, kd, gamma (0.3), width (sigma, 30), centres: dict
    ``{"method": "sobol" | "latin_hypercube" | "grid", ...}`` (see
    :mod:`neurov.centres`), or an explicit (N, 24) array; modification,
    sigma_m, kappa, w_max, dead_zone.
    linear: ``lambda_``, kd, gamma (number or 24), theta0: ``"zero"``,
    ``"true"`` (the plant's own theta) or ``"scaled"`` (true times
    theta0_scale).
    pd: kp, kd.
    pid: kp, ki, kd, integral_limit (largest ``|K_i z|`` per DOF).
    smc: ``lambda_``, kd, k (switching gain), phi (boundary layer); the nominal
    model is the vehicle file's theta (regressor_parameters).
    """

    type: str = "nn"
    label: str = ""
    lambda_: NDArray[np.float64] = field(default_factory=lambda: np.full(6, 0.5))
    kd: NDArray[np.float64] = field(default_factory=lambda: np.array([200.0, 200, 200, 50, 50, 50]))
    kp: NDArray[np.float64] = field(default_factory=lambda: np.zeros(6))
    gamma: float | NDArray[np.float64] = 0.3
    width: float = 30.0
    centres: Any = field(default_factory=lambda: {"method": "sobol", "n": 64})
    modification: str = "none"
    sigma_m: float = 0.0
    kappa: float = 0.0
    w_max: float = 0.0
    dead_zone: float = 0.0
    theta0: str = "zero"
    theta0_scale: float = 1.0
    ki: NDArray[np.float64] = field(default_factory=lambda: np.zeros(6))
    integral_limit: NDArray[np.float64] = field(default_factory=lambda: np.full(6, 50.0))
    k: NDArray[np.float64] = field(default_factory=lambda: np.zeros(6))
    phi: NDArray[np.float64] = field(default_factory=lambda: np.full(6, 0.1))

    @property
    def name(self) -> str:
        names = {"nn": "NN adaptive", "linear": "linear adaptive", "pd": "PD", "pid": "PID",
                 "smc": "sliding mode"}
        return self.label or names.get(self.type, self.type)


@dataclass
class CommandSpec:
    """Commanded trajectory: ``type`` is ``"waypoints"`` (``times``, ``poses``)
    or a generator of :mod:`neurov.trajectories` with its keyword ``args``."""

    type: str = "square"
    args: dict[str, Any] = field(default_factory=dict)
    times: NDArray[np.float64] | None = None
    poses: NDArray[np.float64] | None = None
    interpolation: str = "linear"

    def timed_poses(self) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        if self.type == "waypoints":
            return trajectories.waypoints(self.times, self.poses)
        generator = getattr(trajectories, self.type)
        return generator(**self.args)  # type: ignore[no-any-return]


@dataclass
class Disturbance:
    """amplitude * sin(2 pi frequency (t - start) + phase) in body DOF `dof` (0..5)."""

    dof: int = 5
    amplitude: float = 0.0
    frequency: float = 0.0
    phase: float = 0.0
    start: float = 0.0


@dataclass
class ThrusterFailure:
    index: int = 0
    efficiency: float = 0.0
    time: float = 0.0


@dataclass
class SensorFault:
    """Over [start, end) the measurement freezes, drops out (NaN) or gets extra
    noise (noise_burst: noise_eta, noise_nu standard deviations); `eta` and
    `nu` say which measurement is affected."""

    kind: str = "freeze"
    start: float = 0.0
    end: float = 0.0
    eta: bool = True
    nu: bool = True
    noise_eta: NDArray[np.float64] = field(default_factory=lambda: np.zeros(6))
    noise_nu: NDArray[np.float64] = field(default_factory=lambda: np.zeros(6))


@dataclass
class CurrentStep:
    """From `time` on the mean current is `velocity` (NED, m/s)."""

    time: float = 0.0
    velocity: NDArray[np.float64] = field(default_factory=lambda: np.zeros(3))


@dataclass
class Scenario:
    name: str = "scenario"
    description: str = ""
    duration: float = 200.0
    dt: float = 0.2
    substeps: int = 10
    seed: int = 0
    vehicle: str = "nerov"
    """A preset name or a path to a vehicle file."""
    vehicle_parameters: dict[str, Any] | None = None
    """Overrides of the vehicle's parameters (e.g. for a perturbed plant)."""
    use_thrusters: bool = False
    eta0: NDArray[np.float64] = field(default_factory=lambda: np.zeros(6))
    nu0: NDArray[np.float64] = field(default_factory=lambda: np.zeros(6))
    lambda_d: NDArray[np.float64] = field(default_factory=lambda: np.full(6, 1.0))
    omega: NDArray[np.float64] = field(default_factory=lambda: np.full(6, 0.25))
    command: CommandSpec = field(default_factory=CommandSpec)
    controller: ControllerSpec = field(default_factory=ControllerSpec)
    disturbances: list[Disturbance] = field(default_factory=list)
    current: NDArray[np.float64] = field(default_factory=lambda: np.zeros(3))
    current_amplitude: NDArray[np.float64] = field(default_factory=lambda: np.zeros(3))
    current_period: float = 0.0
    noise_eta: NDArray[np.float64] = field(default_factory=lambda: np.zeros(6))
    noise_nu: NDArray[np.float64] = field(default_factory=lambda: np.zeros(6))
    saturation: str = "scale"
    thruster_time_constant: float | None = None
    """Thruster lag [s]; None takes the vehicle file's (0, none, if it gives none)."""
    thruster_failures: list[ThrusterFailure] = field(default_factory=list)
    sensor_faults: list[SensorFault] = field(default_factory=list)
    current_steps: list[CurrentStep] = field(default_factory=list)
    refused_step_policy: str = "zero"
    """What the loop applies when the controller refuses a step: "zero" (the
    controller's own tau = 0) or "hold" (its last accepted tau)."""
    source: str = ""
    """The file the scenario came from, if any (vehicle paths are relative to it)."""
    vehicle_file: VehicleFile | None = field(default=None, repr=False, compare=False)
    """The vehicle file as read when the scenario was loaded (see vehicle_data())."""

    def replace(self, **changes: Any) -> Scenario:
        """A copy with some fields changed (``dataclasses.replace``)."""
        return dataclasses.replace(self, **changes)

    def with_controller(self, controller: ControllerSpec) -> Scenario:
        return self.replace(controller=controller)

    @staticmethod
    def from_file(path: str | Path) -> Scenario:
        return load_scenario(path)

    def vehicle_data(self) -> VehicleFile:
        """The vehicle file, read and checked once: the copy the scenario holds
        while it still names the same file, else the file read now (and held)."""
        path = self.vehicle_path()
        if self.vehicle_file is None or self.vehicle_file.path != path:
            self.vehicle_file = read_vehicle_file(path)
        return self.vehicle_file

    def vehicle_path(self) -> Path:
        p = Path(self.vehicle)
        if p.suffix == ".toml":
            if not p.is_absolute() and self.source:
                p = Path(self.source).parent / p
            return p
        return preset_path(self.vehicle)


def _controller(r: _Reader) -> ControllerSpec:
    kind = r.string("type", choices=("nn", "linear", "pd", "pid", "smc"))
    spec = ControllerSpec(type=kind, label=r.string("label", ""))
    if kind in ("nn", "linear", "smc"):
        spec.lambda_ = r.array("lambda", 6, spec.lambda_, positive=True)
    spec.kd = r.array("kd", 6, spec.kd, non_negative=True)
    if kind in ("pd", "pid"):
        spec.kp = r.array("kp", 6, non_negative=True)
    if kind == "pid":
        spec.ki = r.array("ki", 6, non_negative=True)
        spec.integral_limit = r.array("integral_limit", 6, spec.integral_limit, positive=True)
    if kind == "smc":
        spec.k = r.array("k", 6, non_negative=True)
        spec.phi = r.array("phi", 6, spec.phi, positive=True)
    if kind == "nn":
        spec.gamma = r.number("gamma", 0.3, minimum=0.0)
        spec.width = r.number("width", 30.0, positive=True)
        spec.modification = r.string(
            "modification", "none", choices=("none", "sigma", "e_modification", "projection")
        )
        spec.sigma_m = r.number("sigma_m", 0.0, minimum=0.0)
        spec.kappa = r.number("kappa", 0.0, minimum=0.0)
        spec.w_max = r.number("w_max", 0.0, minimum=0.0)
        spec.dead_zone = r.number("dead_zone", 0.0, minimum=0.0)
        c = r.table_of("centres")
        method = c.string("method", "sobol", choices=("sobol", "latin_hypercube", "grid"))
        centres: dict[str, Any] = {"method": method}
        if method == "grid":
            axes = c.raw("axes", None)
            if not isinstance(axes, Mapping) or not axes:
                raise c.error("axes", "expected a table {input = [low, high, count], ...}")
            centres["axes"] = {}
            for k, v in axes.items():
                if not (isinstance(v, list) and len(v) == 3):
                    raise c.error(f"axes.{k}", "expected [low, high, count]")
                centres["axes"][k] = (float(v[0]), float(v[1]), int(v[2]))
        else:
            centres["n"] = c.integer("n", 64, minimum=1)
            centres["seed"] = c.integer("seed", 0)
            centres["low"] = c.array("low", 24, None) if c.has("low") else None
            centres["high"] = c.array("high", 24, None) if c.has("high") else None
        c.finish()
        spec.centres = centres
    if kind == "linear":
        g = r.raw("gamma", 1.0)
        if isinstance(g, list):
            spec.gamma = r.array("gamma", 24, non_negative=True)
        else:
            spec.gamma = r.number("gamma", 1.0, minimum=0.0)
        spec.theta0 = r.string("theta0", "zero", choices=("zero", "true", "scaled"))
        spec.theta0_scale = r.number("theta0_scale", 1.0)
    r.finish()
    return spec


def _command(r: _Reader) -> CommandSpec:
    kind = r.string("type", choices=("waypoints", "square", "lawnmower", "circle", "helix"))
    spec = CommandSpec(type=kind, interpolation=r.string("interpolation", "linear", choices=("linear", "hold")))
    if kind == "waypoints":
        times = r.raw("times")
        poses = r.raw("poses")
        try:
            spec.times, spec.poses = trajectories.waypoints(times, poses)
        except (ValueError, TypeError) as e:
            raise r.error("times/poses", str(e)) from None
    else:
        args = {k: v for k, v in r.table.items() if k not in ("type", "interpolation")}
        generator = getattr(trajectories, kind)
        try:
            generator(**args)
        except TypeError as e:
            raise r.error("type", f"bad arguments for {kind!r}: {e}") from None
        except ValueError as e:
            raise r.error(kind, str(e)) from None
        spec.args = args
        r.used |= set(args)
    r.finish()
    return spec


def scenario_from_mapping(data: Mapping[str, Any], origin: str = "<scenario>") -> Scenario:
    """Builds a scenario from a parsed TOML table; errors name `origin`."""
    r = _Reader(data, "", origin)
    s = Scenario(source=origin if origin != "<scenario>" else "")
    s.name = r.string("name", Path(origin).stem if origin != "<scenario>" else "scenario")
    s.description = r.string("description", "")
    s.duration = r.number("duration", s.duration, positive=True)
    s.dt = r.number("dt", s.dt, positive=True)
    s.substeps = r.integer("substeps", s.substeps, minimum=1)
    s.seed = r.integer("seed", 0)
    v = r.table_of("vehicle")
    if v.has("preset") and v.has("file"):
        raise v.error("file", "give either 'preset' or 'file', not both")
    s.vehicle = v.string("file") if v.has("file") else v.string("preset", "nerov")
    s.use_thrusters = v.boolean("thrusters", False)
    s.saturation = v.string("saturation", "scale", choices=("scale", "clip"))
    if v.has("thruster_time_constant"):
        s.thruster_time_constant = v.number("thruster_time_constant", minimum=0.0)
    if v.has("parameters"):
        over = v.raw("parameters")
        if not isinstance(over, Mapping):
            raise v.error("parameters", "expected a table of vehicle parameters")
        s.vehicle_parameters = dict(over)
    v.finish()
    try:
        vehicle = s.vehicle_data()
    except (VehicleFileError, ValueError) as e:
        raise ScenarioError(f"{origin}: vehicle: {e}") from None
    thrusters = vehicle.thrusters if s.use_thrusters else None
    if s.use_thrusters and thrusters is None:
        raise v.error("thrusters", f"the vehicle file {vehicle.path} has no [thrusters] table")
    i = r.table_of("initial")
    s.eta0 = i.array("eta", 6, s.eta0, broadcast=False)
    s.nu0 = i.array("nu", 6, s.nu0, broadcast=False)
    i.finish()
    ref = r.table_of("reference")
    s.lambda_d = ref.array("lambda_d", 6, s.lambda_d, positive=True)
    s.omega = ref.array("omega", 6, s.omega, positive=True)
    ref.finish()
    if not r.has("command"):
        raise r.error("command", "missing (expected a table with 'type')")
    s.command = _command(r.table_of("command"))
    if not r.has("controller"):
        raise r.error("controller", "missing (expected a table with 'type')")
    s.controller = _controller(r.table_of("controller"))
    dist = r.raw("disturbances", [])
    if not isinstance(dist, list):
        raise r.error("disturbances", "expected an array of tables [[disturbances]]")
    for k, d in enumerate(dist):
        dr = _Reader(d, f"disturbances[{k}]", origin)
        s.disturbances.append(
            Disturbance(
                dof=_dof(dr, "dof"),
                amplitude=dr.number("amplitude"),
                frequency=dr.number("frequency", 0.0, minimum=0.0),
                phase=dr.number("phase", 0.0),
                start=dr.number("start", 0.0),
            )
        )
        dr.finish()
    c = r.table_of("current")
    s.current = c.array("velocity", 3, s.current, broadcast=False)
    s.current_amplitude = c.array("amplitude", 3, s.current_amplitude, broadcast=False)
    s.current_period = c.number("period", 0.0, minimum=0.0)
    c.finish()
    n = r.table_of("noise")
    s.noise_eta = n.array("eta", 6, s.noise_eta, non_negative=True)
    s.noise_nu = n.array("nu", 6, s.noise_nu, non_negative=True)
    n.finish()
    fails = r.raw("thruster_failures", [])
    if not isinstance(fails, list):
        raise r.error("thruster_failures", "expected an array of tables [[thruster_failures]]")
    for k, f in enumerate(fails):
        fr = _Reader(f, f"thruster_failures[{k}]", origin)
        eff = fr.number("efficiency", 0.0, minimum=0.0)
        if eff > 1:
            raise fr.error("efficiency", f"expected a number in [0, 1], got {eff}")
        failure = ThrusterFailure(index=fr.integer("index"), efficiency=eff, time=fr.number("time", 0.0))
        if thrusters is not None and failure.index >= thrusters["matrix"].shape[1]:
            raise fr.error("index", f"expected a thruster index 0..{thrusters['matrix'].shape[1] - 1}, "
                                    f"got {failure.index}")
        s.thruster_failures.append(failure)
        fr.finish()
    faults = r.raw("sensor_faults", [])
    if not isinstance(faults, list):
        raise r.error("sensor_faults", "expected an array of tables [[sensor_faults]]")
    for k, f in enumerate(faults):
        fr = _Reader(f, f"sensor_faults[{k}]", origin)
        fault = SensorFault(
            kind=fr.string("kind", choices=("freeze", "dropout", "noise_burst")),
            start=fr.number("start"),
            end=fr.number("end"),
            eta=fr.boolean("eta", True),
            nu=fr.boolean("nu", True),
            noise_eta=fr.array("noise_eta", 6, np.zeros(6), non_negative=True),
            noise_nu=fr.array("noise_nu", 6, np.zeros(6), non_negative=True),
        )
        if fault.end < fault.start:
            raise fr.error("end", f"expected end >= start ({fault.start}), got {fault.end}")
        s.sensor_faults.append(fault)
        fr.finish()
    steps = r.raw("current_steps", [])
    if not isinstance(steps, list):
        raise r.error("current_steps", "expected an array of tables [[current_steps]]")
    for k, cs in enumerate(steps):
        cr = _Reader(cs, f"current_steps[{k}]", origin)
        step = CurrentStep(time=cr.number("time"), velocity=cr.array("velocity", 3, broadcast=False))
        if s.current_steps and step.time <= s.current_steps[-1].time:
            raise cr.error("time", "expected times in increasing order")
        s.current_steps.append(step)
        cr.finish()
    s.refused_step_policy = r.string("refused_step_policy", "zero", choices=("zero", "hold"))
    if s.thruster_failures and not s.use_thrusters:
        raise r.error("thruster_failures", "needs [vehicle] thrusters = true")
    r.finish()
    return s


def load_scenario(path: str | Path) -> Scenario:
    """Reads a scenario file; raises :class:`ScenarioError` naming the file and field."""
    path = Path(path)
    try:
        data = tomllib.loads(read_text(path, ScenarioError))
    except FileNotFoundError:
        raise ScenarioError(f"{path}: no such scenario file") from None
    except tomllib.TOMLDecodeError as e:
        raise ScenarioError(f"{path}: not valid TOML: {e}") from None
    return scenario_from_mapping(data, str(path))


def make_centres(spec: ControllerSpec, low: NDArray[np.float64], high: NDArray[np.float64]) -> NDArray[np.float64]:
    """The (N, 24) centres a controller spec asks for; `low`/`high` is the box
    used when the spec gives none."""
    c = spec.centres
    if isinstance(c, np.ndarray):
        return np.asarray(c, dtype=np.float64)
    method = c.get("method", "sobol")
    if method == "grid":
        return centre_placement.grid(c["axes"])
    lo = low if c.get("low") is None else np.asarray(c["low"], dtype=np.float64)
    hi = high if c.get("high") is None else np.asarray(c["high"], dtype=np.float64)
    fn = centre_placement.sobol if method == "sobol" else centre_placement.latin_hypercube
    return fn(int(c.get("n", 64)), lo, hi, seed=int(c.get("seed", 0)))
