"""Reading a scenario file (TOML) into a :class:`neurov.config.scenario.Scenario`.

The reader checks what TOML can get wrong (a missing key, a string where a
number goes, the wrong number of elements) and puts each value into the
core's config struct; the rules (a gain >= 0, increasing times, a thruster
index in range) are the C++ validators', whose messages come back naming
the file and the TOML key: ``square.toml: controller.kd[3] = -1: expected
>= 0 and finite``.
"""

from __future__ import annotations

import copy
import difflib
import math
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from neurov import _core
from neurov.config import trajectories
from neurov.files import read_toml
from neurov.config.scenario import CommandSpec, ControllerSpec, Scenario, ScenarioError
from neurov.config.realism import REALISM_KEYS, read_realism
from neurov.config.schema import SchemaError, convert, field_names
from neurov.errors import ValidationError
from neurov.config.vehicle_file import VehicleFileError

__all__ = ["read_scenario", "scenario_from_mapping"]

DOF_NAMES = ("surge", "sway", "heave", "roll", "pitch", "yaw")


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

    def _lookup(self, key: str, default: Any, expected: str) -> tuple[bool, Any]:
        """(True, the value) when the table has `key`; else (False, the
        default), or an error naming what was `expected` without one."""
        self.used.add(key)
        if key in self.table:
            return True, self.table[key]
        if default is None:
            raise self.error(key, f"missing (expected {expected})")
        return False, default

    def number(self, key: str, default: float | None = None, *, minimum: float | None = None,
               positive: bool = False) -> float:
        found, v = self._lookup(key, default, "a number")
        if not found:
            return v
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

    def integer(self, key: str, default: int | None = None, *, minimum: int = 0,
                maximum: tuple[int, str] | None = None) -> int:
        """`maximum`: a count's bound and its name, checked before the
        count is used (it would not fit a C++ int, or would allocate)."""
        found, v = self._lookup(key, default, "an integer")
        if not found:
            return v
        if isinstance(v, bool) or not isinstance(v, int):
            raise self.error(key, f"expected an integer, got {type(v).__name__} {v!r}")
        if v < minimum:
            raise self.error(key, f"expected an integer >= {minimum}, got {v}")
        if maximum is not None and v > maximum[0]:
            raise self.error(key, f"expected an integer <= {maximum[0]} ({maximum[1]}), got {v}")
        return v

    def string(self, key: str, default: str | None = None, choices: Sequence[str] | None = None) -> str:
        found, v = self._lookup(key, default, "a string")
        if not found:
            return v
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
        found, v = self._lookup(key, default, f"{length} numbers")
        if not found:
            return np.array(v, dtype=np.float64)
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


def _validated(config: Any, origin: str, keys: Mapping[str, str], lists: Sequence[str] = ()) -> None:
    """Runs the config's C++ validator; its refusal comes back naming the
    file and the TOML key (`keys`: config field -> TOML key; for the `lists`
    of tables, ``name.field[i]`` reads ``name[i].field``)."""
    try:
        config.validate()
    except ValidationError as e:
        name, index = e.field, (e.index if e.index >= 0 else None)
        head, _, sub = name.partition(".")
        if head in lists and index is not None:
            key = f"{keys.get(head, head)}[{index}]" + (f".{sub}" if sub else "")
        else:
            key = keys.get(name, name) + (f"[{index}]" if index is not None else "")
        value = "" if e.value is None else f" = {e.value:.9g}"
        raise ScenarioError(f"{origin}: {key}{value}: expected {e.expected}") from None


def _controller(r: _Reader) -> ControllerSpec:
    """A controller table: the type's config fields by their TOML names (the
    C++ defaults where absent), then its Python options."""
    from neurov.laws.registry import REGISTRY

    kind = REGISTRY[r.string("type", choices=tuple(REGISTRY))]
    spec = ControllerSpec(kind.name, label=r.string("label", ""))
    for key in kind.fields():
        if r.has(key):
            name = kind.keys.get(key, key)
            try:
                setattr(spec.config, name, convert(getattr(spec.config, name), r.raw(key), r._name(key)))
            except SchemaError as e:
                raise ScenarioError(f"{r.origin}: {e}") from None
    if kind.name == "nn":
        spec.width = r.number("width", spec.width)
        # "si": the paper's inputs in SI units; "normalised": the scenario's centre box mapped onto [-1, 1].
        spec.inputs = r.string("inputs", spec.inputs, choices=("si", "normalised"))
        spec.centres = _centres(r.table_of("centres"))
    if kind.name == "linear":
        spec.theta0 = r.string("theta0", spec.theta0, choices=("zero", "true", "scaled"))
        spec.theta0_scale = r.number("theta0_scale", spec.theta0_scale)
    r.finish()
    inverse = {v: k for k, v in kind.keys.items()}
    checked = spec.config
    if "vehicle" in kind.managed and checked.vehicle is None or "theta" in kind.managed:
        # The plant model is the scenario's, put in when the controller is
        # built: the gains are checked here beside a valid stand-in.
        checked = copy.copy(checked)
        if "vehicle" in kind.managed:
            checked.vehicle = _core.Vehicle.nerov()
        else:
            checked.theta = _core.regressor_parameters(_core.Vehicle.nerov())
    _validated(checked, r.origin, {n: r._name(inverse.get(n, n)) for n in field_names(spec.config)})
    if kind.name == "nn" and not spec.width > 0:
        raise r.error("width", f"expected a number > 0, got {spec.width}")
    return spec


def _centres(c: _Reader) -> dict[str, Any]:
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
        count = math.prod(a[2] for a in centres["axes"].values())
        if count > _core.MAX_CENTRES:
            raise c.error("axes", f"the grid has {count} centres, more than the {_core.MAX_CENTRES} "
                                  "a network takes (neurov.MAX_CENTRES)")
    else:
        centres["n"] = c.integer("n", 64, minimum=1,
                                 maximum=(_core.MAX_CENTRES, "the most a network takes, neurov.MAX_CENTRES"))
        centres["seed"] = c.integer("seed", 0)
        centres["low"] = c.array("low", 24, None) if c.has("low") else None
        centres["high"] = c.array("high", 24, None) if c.has("high") else None
    c.finish()
    return centres


def _command(r: _Reader) -> CommandSpec:
    kind = r.string("type", choices=("waypoints", "recorded", "square", "lawnmower", "circle", "helix"))
    spec = CommandSpec(type=kind, interpolation=r.string("interpolation", "linear", choices=("linear", "hold")))
    if kind == "recorded":
        from neurov.recording.recorded_path import RecordedPathError, recorded_path

        file = Path(r.string("file"))
        if not file.is_absolute() and r.origin != "<scenario>":
            file = Path(r.origin).parent / file  # beside the scenario file, as a vehicle file is
        spec.args = {"file": str(file), "topic": r.string("topic"), "start": r.number("start", 0.0)}
        try:
            spec.times, spec.poses = recorded_path(**spec.args)
        except RecordedPathError as e:
            raise r.error(e.field, str(e)) from None
    elif kind == "waypoints":
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



# SimulationConfig field -> TOML key, for the validator's messages.
_SIMULATION_KEYS = {
    "eta0": "initial.eta", "nu0": "initial.nu", "lambda_d": "reference.lambda_d",
    "omega": "reference.omega", "current": "current.velocity", "current_amplitude": "current.amplitude",
    "current_period": "current.period", "noise_eta": "noise.eta", "noise_nu": "noise.nu",
    "command.times": "command", "command.poses": "command",
}
_LISTS = ("disturbances", "thruster_failures", "sensor_faults", "current_steps")


def _tables(r: _Reader, key: str) -> list[_Reader]:
    items = r.raw(key, [])
    if not isinstance(items, list):
        raise r.error(key, f"expected an array of tables [[{key}]]")
    return [_Reader(t, f"{key}[{k}]", r.origin) for k, t in enumerate(items)]


def scenario_from_mapping(data: Mapping[str, Any], origin: str = "<scenario>") -> Scenario:
    """Builds a scenario from a parsed TOML table; errors name `origin`."""
    from neurov.config import sea

    r = _Reader(data, "", origin)
    s = Scenario(source=origin if origin != "<scenario>" else "")
    c = s.simulation
    d = s.__dict__
    d["name"] = r.string("name", Path(origin).stem if origin != "<scenario>" else "scenario")
    d["description"] = r.string("description", "")
    c.duration = r.number("duration", c.duration)
    c.dt = r.number("dt", c.dt)
    c.substeps = r.integer("substeps", c.substeps, minimum=-(2**31),
                           maximum=(_core.MAX_SUBSTEPS, "neurov.MAX_SUBSTEPS"))
    try:
        c.seed = r.integer("seed", c.seed)
    except ValueError as e:  # the core's range check, which gives the range
        if isinstance(e, ScenarioError):
            raise
        raise r.error("seed", str(e).removeprefix("SimulationConfig.seed ")) from None
    v = r.table_of("vehicle")
    if v.has("preset") and v.has("file"):
        raise v.error("file", "give either 'preset' or 'file', not both")
    d["vehicle"] = v.string("file") if v.has("file") else v.string("preset", "nerov")
    c.use_thrusters = v.boolean("thrusters", False)
    saturation = v.string("saturation", "scale", choices=tuple(_core.Saturation.__members__))
    c.thrusters.saturation = _core.Saturation.__members__[saturation]
    if v.has("thruster_time_constant"):
        d["thruster_time_constant"] = v.number("thruster_time_constant")
    if v.has("parameters"):
        over = v.raw("parameters")
        if not isinstance(over, Mapping):
            raise v.error("parameters", "expected a table of vehicle parameters")
        d["vehicle_parameters"] = dict(over)
    v.finish()
    try:
        vehicle = s.vehicle_data()
    except (VehicleFileError, ValueError) as e:
        raise ScenarioError(f"{origin}: vehicle: {e}") from None
    if c.use_thrusters and vehicle.thrusters is None:
        raise v.error("thrusters", f"the vehicle file {vehicle.path} has no [thrusters] table")
    i = r.table_of("initial")
    c.eta0 = i.array("eta", 6, c.eta0, broadcast=False)
    c.nu0 = i.array("nu", 6, c.nu0, broadcast=False)
    i.finish()
    ref = r.table_of("reference")
    c.lambda_d = ref.array("lambda_d", 6, c.lambda_d)
    c.omega = ref.array("omega", 6, c.omega)
    ref.finish()
    if not r.has("command"):
        raise r.error("command", "missing (expected a table with 'type')")
    d["command"] = _command(r.table_of("command"))
    if not r.has("controller"):
        raise r.error("controller", "missing (expected a table with 'type')")
    d["controller"] = _controller(r.table_of("controller"))
    disturbances = []
    for dr in _tables(r, "disturbances"):
        disturbances.append(_core.SinusoidalDisturbance(
            dof=_dof(dr, "dof"), amplitude=dr.number("amplitude"), frequency=dr.number("frequency", 0.0),
            phase=dr.number("phase", 0.0), start=dr.number("start", 0.0)))
        dr.finish()
    c.disturbances = disturbances
    cr = r.table_of("current")
    if sea.read_current_model(cr, c):
        c.current = cr.array("velocity", 3, c.current, broadcast=False)
        c.current_amplitude = cr.array("amplitude", 3, c.current_amplitude, broadcast=False)
        c.current_period = cr.number("period", c.current_period)
    cr.finish()
    sea.read_sea(r, c)
    n = r.table_of("noise")
    c.noise_eta = n.array("eta", 6, c.noise_eta)
    c.noise_nu = n.array("nu", 6, c.noise_nu)
    n.finish()
    failures = []
    for fr in _tables(r, "thruster_failures"):
        failures.append(_core.ThrusterFailure(index=fr.integer("index", minimum=-(2**31)),
                                              efficiency=fr.number("efficiency", 0.0), time=fr.number("time", 0.0)))
        fr.finish()
    c.thruster_failures = failures
    faults = []
    for fr in _tables(r, "sensor_faults"):
        kind = fr.string("kind", choices=tuple(_core.SensorFaultKind.__members__))
        faults.append(_core.SensorFault(
            kind=_core.SensorFaultKind.__members__[kind], start=fr.number("start"), end=fr.number("end"),
            eta=fr.boolean("eta", True), nu=fr.boolean("nu", True),
            noise_eta=fr.array("noise_eta", 6, np.zeros(6)), noise_nu=fr.array("noise_nu", 6, np.zeros(6))))
        fr.finish()
    c.sensor_faults = faults
    steps = []
    for sr in _tables(r, "current_steps"):
        steps.append(_core.CurrentStep(time=sr.number("time"), velocity=sr.array("velocity", 3, broadcast=False)))
        sr.finish()
    c.current_steps = steps
    policy = r.string("refused_step_policy", "zero", choices=tuple(_core.RefusedStepPolicy.__members__))
    c.refused_step_policy = _core.RefusedStepPolicy.__members__[policy]
    read_realism(r, c)
    r.finish()
    try:
        s._sync()
    except ValueError as e:
        raise ScenarioError(f"{origin}: {e}") from None
    sea.check_payload(s, origin)
    _validated(c, origin, {**_SIMULATION_KEYS, **REALISM_KEYS}, _LISTS)
    return s


def read_scenario(path: str | Path) -> Scenario:
    """Reads a scenario file; raises :class:`ScenarioError` naming the file and field."""
    path = Path(path)
    return scenario_from_mapping(read_toml(path, ScenarioError, "scenario"), str(path))
