"""Reading a scenario file (TOML) into a :class:`neurov.config.scenario.Scenario`.

The reader checks what TOML can get wrong (a missing key, a string where a
number goes, the wrong number of elements) and puts each value into the
core's config struct; the rules (a gain >= 0, increasing times, a thruster
index in range) are the C++ validators', whose messages come back naming
the file and the TOML key: ``square.toml: controller.kd[3] = -1: expected
>= 0 and finite``.

A scenario file (all tables but ``[command]`` and ``[controller]`` optional)::

    name = "square"
    duration = 200.0        # s
    dt = 0.2                # control period, s (the paper: 5 Hz)
    substeps = 10           # RK4 plant steps per control period, 1..10000 (neurov.MAX_SUBSTEPS)
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
    side = 10.0             # the generator's arguments (neurov.config.trajectories)

    [controller]
    type = "nn"             # nn | linear | pd | pid | smc | computed_torque
    lambda = 0.5
    kd = [200, 200, 200, 50, 50, 50]

    [controller.centres]    # the NN's centres: sobol | latin_hypercube | grid | path
    n = 64                  # at most 65536 (neurov.MAX_CENTRES; a grid's too)

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
"""

from __future__ import annotations

import copy
import math
import warnings
from collections.abc import Mapping
from pathlib import Path
from typing import Any

import numpy as np

from neurov import _core, hooks
from neurov.config import sea, trajectories
from neurov.files import read_toml
from neurov.config.scenario import CommandSpec, ControllerSpec, Scenario, ScenarioError, vehicle_path
from neurov.config.realism import REALISM_KEYS, read_realism
from neurov.errors import RecordedPathError
from neurov.schema import SchemaError, convert, field_names
from neurov.config.vehicle_file import VehicleFileError, read_vehicle_file
from neurov.config.toml_table import TableReader, tables, validated
from neurov.laws import ardusub_params as ardusub
from neurov.laws.registry import REGISTRY

__all__ = ["load_scenario", "read_controller", "read_scenario", "scenario_from_mapping"]

DOF_NAMES = ("surge", "sway", "heave", "roll", "pitch", "yaw")


def _dof(reader: TableReader, key: str) -> int:
    v = reader.raw(key)
    if isinstance(v, str) and v in DOF_NAMES:
        return DOF_NAMES.index(v)
    if isinstance(v, int) and not isinstance(v, bool) and 0 <= v <= 5:
        return v
    raise reader.error(key, f"expected one of {list(DOF_NAMES)} or 0..5, got {v!r}")


def read_controller(r: TableReader) -> ControllerSpec:
    """A controller table: the type's config fields by their TOML names (the
    C++ defaults where absent), then its Python options."""
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
    if kind.name == "ardusub":
        _ardusub_options(r, spec, kind.fields())
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
    validated(checked, r.origin, {n: r._name(inverse.get(n, n)) for n in field_names(spec.config)})
    if kind.name == "nn" and not spec.width > 0:
        raise r.error("width", f"expected a number > 0, got {spec.width}")
    return spec


def _ardusub_options(r: TableReader, spec: ControllerSpec, fields: list[str]) -> None:
    """ArduSub's ``mode`` and ``params`` (a .param, .tlog or .bin beside the
    scenario file): the file's values under the table's own keys."""
    spec.config.mode = float(ardusub.MODES[r.string("mode", "depth_hold", choices=tuple(ardusub.MODES))])
    given = {k for k in fields if k in r.table}
    for key in sorted(given & set(ardusub.PARAMETERS)):
        note = ardusub.out_of_range(key, float(getattr(spec.config, key)))
        if note:
            warnings.warn(f"{r.origin}: controller.{note}", ardusub.ArduSubRangeWarning, stacklevel=3)
    spec.params = r.string("params", "")
    if spec.params:
        file = Path(spec.params)
        if not file.is_absolute() and r.origin != "<scenario>":
            file = Path(r.origin).parent / file  # beside the scenario file, as a vehicle file is
        try:
            ardusub.apply_parameters(spec.config, ardusub.read_parameters(file), str(file), skip=given)
        except ardusub.ArduSubParameterError as e:
            raise r.error("params", str(e)) from None


def _centres(c: TableReader) -> dict[str, Any]:
    method = c.string("method", "sobol", choices=("sobol", "latin_hypercube", "grid", "path"))
    centres: dict[str, Any] = {"method": method}
    if method == "path":
        # On the scenario's desired trajectory (neurov.laws.path_centres): no box to give.
        centres["n"] = c.integer("n", 64, minimum=1,
                                 maximum=(_core.MAX_CENTRES, "the most a network takes, neurov.MAX_CENTRES"))
        centres["seed"] = c.integer("seed", 0)
    elif method == "grid":
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


def _command(r: TableReader) -> CommandSpec:
    kind = r.string("type", choices=("waypoints", "recorded", "square", "lawnmower", "circle", "helix"))
    spec = CommandSpec(type=kind, interpolation=r.string("interpolation", "linear", choices=("linear", "hold")))
    if kind == "recorded":
        file = Path(r.string("file"))
        if not file.is_absolute() and r.origin != "<scenario>":
            file = Path(r.origin).parent / file  # beside the scenario file, as a vehicle file is
        spec.args = {"file": str(file), "topic": r.string("topic"), "start": r.number("start", 0.0)}
        try:
            spec.times, spec.poses = hooks.provided("recorded_path")(**spec.args)
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


def scenario_from_mapping(data: Mapping[str, Any], origin: str = "<scenario>") -> Scenario:
    """Builds a scenario from a parsed TOML table; errors name `origin`."""
    r = TableReader(data, "", origin)
    # The scenario's parts, read first: the Scenario is made of them at the end (its config built once).
    c = _core.SimulationConfig()
    d: dict[str, Any] = {"source": origin if origin != "<scenario>" else ""}
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
        d["vehicle_file"] = vehicle = read_vehicle_file(vehicle_path(d["vehicle"], d["source"]))
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
    d["controller"] = read_controller(r.table_of("controller"))
    disturbances = []
    for dr in tables(r, "disturbances"):
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
    for fr in tables(r, "thruster_failures"):
        failures.append(_core.ThrusterFailure(index=fr.integer("index", minimum=-(2**31)),
                                              efficiency=fr.number("efficiency", 0.0), time=fr.number("time", 0.0)))
        fr.finish()
    c.thruster_failures = failures
    faults = []
    for fr in tables(r, "sensor_faults"):
        kind = fr.string("kind", choices=tuple(_core.SensorFaultKind.__members__))
        faults.append(_core.SensorFault(
            kind=_core.SensorFaultKind.__members__[kind], start=fr.number("start"), end=fr.number("end"),
            eta=fr.boolean("eta", True), nu=fr.boolean("nu", True),
            noise_eta=fr.array("noise_eta", 6, np.zeros(6)), noise_nu=fr.array("noise_nu", 6, np.zeros(6))))
        fr.finish()
    c.sensor_faults = faults
    steps = []
    for sr in tables(r, "current_steps"):
        steps.append(_core.CurrentStep(time=sr.number("time"), velocity=sr.array("velocity", 3, broadcast=False)))
        sr.finish()
    c.current_steps = steps
    policy = r.string("refused_step_policy", "zero", choices=tuple(_core.RefusedStepPolicy.__members__))
    c.refused_step_policy = _core.RefusedStepPolicy.__members__[policy]
    read_realism(r, c)
    r.finish()
    try:
        s = Scenario(simulation=c, **d)
    except ValueError as e:
        raise ScenarioError(f"{origin}: {e}") from None
    sea.check_payload(s, origin)
    # Checked once, naming the TOML keys: a run of the scenario as read checks it no more.
    s.run_config(check=lambda config: validated(config, origin, {**_SIMULATION_KEYS, **REALISM_KEYS}, _LISTS))
    return s


def read_scenario(path: str | Path) -> Scenario:
    """Reads a scenario file; raises :class:`ScenarioError` naming the file and field."""
    path = Path(path)
    return scenario_from_mapping(read_toml(path, ScenarioError, "scenario"), str(path))


def load_scenario(path: str | Path) -> Scenario:
    """Reads a scenario file; raises :class:`ScenarioError` naming the file and field."""
    return read_scenario(path)
