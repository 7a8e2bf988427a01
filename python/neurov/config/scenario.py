"""Scenarios: everything one closed-loop run needs, as a dataclass or a TOML file.

A scenario file (TOML) and its keys are described by :mod:`neurov.config.reading`,
which reads it; this module holds what a scenario is.
"""

from __future__ import annotations

import copy
import pickle
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from neurov import _core, hooks
from neurov.config import trajectories
from neurov.errors import ScenarioError
from neurov.files import PACKAGE_DIR, shipped_or_path
from neurov.config.vehicle_file import VehicleFile, preset_path, read_vehicle_file
from neurov.schema import as_dict, field_names
from neurov.laws.registry import REGISTRY

__all__ = [
    "CommandSpec",
    "ControllerSpec",
    "CurrentStep",
    "Disturbance",
    "Scenario",
    "ScenarioError",
    "SensorFault",
    "ThrusterFailure",
    "scenario_path",
    "shipped_scenarios",
    "vehicle_path",
]

# The core's own structs: a scenario holds them as they are.
Disturbance = _core.SinusoidalDisturbance
ThrusterFailure = _core.ThrusterFailure
SensorFault = _core.SensorFault
CurrentStep = _core.CurrentStep


class ControllerSpec:
    """A controller: its ``type`` (a name in :data:`neurov.laws.registry.REGISTRY`, the keys of
    ``neurov._core.BUILT_IN_CONTROLLERS``: ``"nn"``, ``"pd"``, ``"super_twisting"``, ...),
    a ``label``, its gains as the type's bound C++ config (``config``; the C++
    defaults and validator) and the type's Python options (the NN's
    ``width`` and ``centres``; the linear controller's ``theta0`` mode
    ``"zero"``, ``"true"`` or ``"scaled"`` and ``theta0_scale``).

    ``ControllerSpec("pd", kp=..., kd=...)`` sets config fields by keyword;
    ``spec.kd`` reads them.
    """

    def __init__(self, type: str = "nn", label: str = "", config: Any = None, **fields: Any) -> None:
        if type not in REGISTRY:
            raise ValueError(f"controller type must be one of {sorted(REGISTRY)}, got {type!r}")
        kind = REGISTRY[type]
        self.type = type
        self.label = label
        self.options = dict(copy.deepcopy(dict(kind.options)))
        self.config = kind.config() if config is None else config
        for name, value in fields.items():
            setattr(self, name, value)

    def __getattr__(self, name: str) -> Any:
        if name.startswith("__") or name in ("type", "label", "options", "config"):
            raise AttributeError(name)
        if name in self.options:
            return self.options[name]
        try:
            return getattr(self.config, "lambda_" if name in ("lambda", "lambda_") else name)
        except AttributeError:
            raise AttributeError(f"a {self.type!r} controller has no field {name!r}") from None

    def __setattr__(self, name: str, value: Any) -> None:
        if name in ("type", "label", "options", "config"):
            object.__setattr__(self, name, value)
        elif name in self.options:
            self.options[name] = value
        else:
            field_name = "lambda_" if name in ("lambda", "lambda_") else name
            if not hasattr(self.config, field_name):
                raise TypeError(f"a {self.type!r} controller has no field {name!r}")
            setattr(self.config, field_name, value)

    def replace(self, **changes: Any) -> ControllerSpec:
        """A copy with some fields or options changed. A new ``type`` starts
        from that type's defaults and keeps the gains both types have."""
        kind = changes.pop("type", self.type)
        if kind == self.type:
            out = ControllerSpec(kind, self.label, copy.copy(self.config))
            out.options = copy.deepcopy(self.options)
        else:
            out = ControllerSpec(kind, self.label)
            shared = set(field_names(out.config)) & set(field_names(self.config))
            for name in shared:
                setattr(out.config, name, getattr(self.config, name))
        for name, value in changes.items():
            setattr(out, name, value)
        return out

    def __repr__(self) -> str:
        return f"ControllerSpec(type={self.type!r}, label={self.label!r}, config={self.config!r}, options={self.options!r})"

    def describe(self) -> dict[str, Any]:
        """Everything that decides the controller, as plain data."""
        options = {k: (v.tolist() if isinstance(v, np.ndarray) else v) for k, v in self.options.items()}
        return {"type": self.type, "label": self.label, "config": as_dict(self.config), "options": options}

    @property
    def name(self) -> str:
        return self.label or REGISTRY[self.type].title


@dataclass
class CommandSpec:
    """Commanded trajectory: ``type`` is ``"waypoints"`` (``times``, ``poses``),
    ``"recorded"`` (the poses of a bag's topic, ``args`` ``file``, ``topic``
    and ``start`` of :func:`neurov.recording.recorded_path.recorded_path`; its
    ``times`` and ``poses`` as read) or a generator of
    :mod:`neurov.config.trajectories` with its keyword ``args``."""

    type: str = "square"
    args: dict[str, Any] = field(default_factory=dict)
    times: NDArray[np.float64] | None = None
    poses: NDArray[np.float64] | None = None
    interpolation: str = "linear"

    def timed_poses(self) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        if self.type == "recorded" and self.poses is None:
            # The recording bridge reads it (lent through neurov.hooks).
            self.times, self.poses = hooks.provided("recorded_path")(**self.args)
        if self.type in ("waypoints", "recorded"):
            return trajectories.waypoints(self.times, self.poses)
        generator = getattr(trajectories, self.type)
        return generator(**self.args)  # type: ignore[no-any-return]

    def config(self) -> Any:
        """The command as the core's ``Command``."""
        if self.interpolation not in ("linear", "hold"):
            raise ValueError(f"command.interpolation must be 'linear' or 'hold', got {self.interpolation!r}")
        times, poses = self.timed_poses()
        return _core.Command(times=times, poses=poses, linear=self.interpolation == "linear")


# Scenario attribute -> SimulationConfig field: the one list of what a
# scenario keeps in the core's config (the names differ only where shown).
SIMULATION_FIELDS: dict[str, str] = {
    "dt": "dt", "substeps": "substeps", "duration": "duration", "seed": "seed",
    "eta0": "eta0", "nu0": "nu0", "lambda_d": "lambda_d", "omega": "omega",
    "disturbances": "disturbances", "current": "current", "current_amplitude": "current_amplitude",
    "current_period": "current_period", "noise_eta": "noise_eta", "noise_nu": "noise_nu",
    "sensor_faults": "sensor_faults", "current_steps": "current_steps",
    "refused_step_policy": "refused_step_policy", "use_thrusters": "use_thrusters",
    "thruster_failures": "thruster_failures", "control_delay": "control_delay", "water_density": "water_density",
    "current_model": "current_model", "gauss_markov_current": "gauss_markov_current",
    "waves": "waves", "payload": "payload",
}
_ENUMS = {"refused_step_policy": _core.RefusedStepPolicy, "saturation": _core.Saturation,
          "current_model": _core.CurrentModel}


def _enum(name: str, value: Any) -> Any:
    """A bound enum from its member or its name (files and users write names)."""
    enum = _ENUMS.get(name)
    if enum is not None and isinstance(value, str):
        if value not in enum.__members__:
            raise ValueError(f"{name} must be one of {sorted(enum.__members__)}, got {value!r}")
        return enum.__members__[value]
    return value


class Scenario:
    """Everything one closed-loop run needs. The run's settings live in
    ``simulation``, the core's own ``SimulationConfig`` (its defaults, its
    validator), filled in from the command and the vehicle file's thrusters;
    its fields read and write as attributes (``scenario.dt``, ...). The rest
    is Python's: the name, the vehicle (a preset or a file, and parameter
    overrides for a perturbed plant), the command's generator and the
    controller spec."""

    def __init__(self, name: str = "scenario", description: str = "", *, vehicle: str = "nerov",
                 vehicle_parameters: dict[str, Any] | None = None, command: CommandSpec | None = None,
                 controller: ControllerSpec | None = None, source: str = "",
                 simulation: Any = None, saturation: Any = None,
                 thruster_time_constant: float | None = None,
                 vehicle_file: VehicleFile | None = None, _built: Any = None, **settings: Any) -> None:
        d = self.__dict__
        d["name"], d["description"], d["source"] = name, description, source
        d["vehicle"], d["vehicle_parameters"] = vehicle, vehicle_parameters
        d["vehicle_file"] = vehicle_file
        d["command"] = command if command is not None else CommandSpec()
        d["controller"] = controller if controller is not None else ControllerSpec()
        d["thruster_time_constant"] = thruster_time_constant
        """Thruster lag [s]; None takes the vehicle file's."""
        d["simulation"] = sim = copy.copy(simulation) if simulation is not None else _core.SimulationConfig()
        for key, value in settings.items():
            if key not in SIMULATION_FIELDS:
                raise TypeError(f"Scenario() got an unexpected keyword argument {key!r}")
            setattr(sim, SIMULATION_FIELDS[key], _enum(key, value))
        if saturation is not None:
            sim.thrusters.saturation = _enum("saturation", saturation)
        d["_built"] = _built  # what `simulation` was built from (replace's copy: see run_config)
        self.run_config(check=False)

    # --- the config's fields as attributes -----------------------------------
    def __getattr__(self, name: str) -> Any:
        sim = self.__dict__.get("simulation")
        if sim is not None and name in SIMULATION_FIELDS:
            return getattr(sim, SIMULATION_FIELDS[name])
        raise AttributeError(f"'Scenario' object has no attribute {name!r}")

    def __setattr__(self, name: str, value: Any) -> None:
        self.__dict__["_checked"] = False
        if name in SIMULATION_FIELDS:
            setattr(self.__dict__["simulation"], SIMULATION_FIELDS[name], _enum(name, value))
            if name == "use_thrusters":
                self._sync()
        elif name == "saturation":
            self.__dict__["simulation"].thrusters.saturation = _enum(name, value)
        elif name in self.__dict__:
            self.__dict__[name] = value
            if name in ("command", "vehicle", "thruster_time_constant", "source"):
                self._sync()
        else:
            raise AttributeError(f"'Scenario' object has no attribute {name!r}")

    @property
    def simulation(self) -> Any:
        """The core's ``SimulationConfig`` of the run, to read or change (once
        handed out, it is checked again before the next run)."""
        self.__dict__["_checked"] = False
        return self.__dict__["simulation"]

    @property
    def saturation(self) -> Any:
        """How the thrusters saturate (Saturation.scale keeps the direction)."""
        return self.__dict__["simulation"].thrusters.saturation

    def run_config(self, check: Callable[[Any], None] | bool = True) -> Any:
        """The core's config of the run, the one the scenario holds: built again
        (:meth:`_sync`) only if what it is built from (the command spec, the
        vehicle file, the thruster settings) changed since it was built, and
        checked by `check` (True: the C++ validator; a ValueError names the
        field) unless it was checked since it was built, changed through the
        scenario or handed out as :attr:`simulation`."""
        d = self.__dict__
        built, (key, held) = d.get("_built"), self._inputs()
        if built is None or built[0] != key or built[1] is not held:
            self._sync()
        if check and not d.get("_checked"):
            if check is True:
                d["simulation"].validate()
            else:
                check(d["simulation"])
            d["_checked"] = True
        return d["simulation"]

    def _inputs(self) -> tuple[tuple[Any, ...], Any]:
        """What :meth:`_sync` builds the config from: a key to compare with
        ``==`` and the vehicle file held (compared by identity)."""
        d, c = self.__dict__, self.command
        sim = d["simulation"]
        try:  # the command spec whole, arrays and all (a spec changed in place is seen)
            command: Any = pickle.dumps((c.type, c.interpolation, c.args, c.times, c.poses))
        except Exception:  # noqa: BLE001 - an argument pickle cannot take: the command is built every time
            command = object()
        if not sim.use_thrusters:
            return (command, False), None
        return (command, True, self.vehicle_path(), d["thruster_time_constant"], sim.water_density,
                sim.thrusters.saturation), d["vehicle_file"]

    def _sync(self) -> None:
        """The config's command from the command spec and its thrusters from
        the vehicle file, so that the config is the whole run."""
        d = self.__dict__
        sim = d["simulation"]
        d["_built"], d["_checked"] = None, False
        try:
            sim.command = self.command.config()
            whole = True
        except (TypeError, ValueError):
            whole = False  # a bad command is named when the scenario is validated or run
        if sim.use_thrusters:
            t = self.vehicle_data().thrusters
            if t is None:
                raise ValueError(f"scenario {self.name!r}: vehicle file {self.vehicle_path()} has no "
                                 "[thrusters] table")
            tc = t["time_constant"] if self.thruster_time_constant is None else self.thruster_time_constant
            curves = list(t["curves"] or [])
            if curves and self.thruster_time_constant is not None:
                # With curves the lag is each curve's: the override goes there.
                curves = [copy.copy(c) for c in curves]
                for c in curves:
                    c.time_constant = tc
                tc = 0.0
            sim.thrusters = _core.ThrusterConfig(
                matrix=t["matrix"], max_thrust=t["max_thrust"], min_thrust=t["min_thrust"],
                saturation=sim.thrusters.saturation, time_constant=tc, curves=curves,
                supply_voltage=t["supply_voltage"])
        if whole:
            d["_built"] = self._inputs()

    def describe(self) -> dict[str, Any]:
        """Everything that decides a run, as plain data (for hashing)."""
        import dataclasses

        command = {k: (v.tolist() if isinstance(v, np.ndarray) else v)
                   for k, v in dataclasses.asdict(self.command).items()}
        simulation = as_dict(self.__dict__["simulation"])
        # A run without a disturbance part added after waves and payload (the
        # tether, ...) describes itself as before that part existed: its
        # studies keep their fingerprints, and so their folders.
        for key, _, _ in _core.DISTURBANCE_TABLES:
            if key not in ("waves", "payload") and simulation.get(key, 0) in (None, []):
                del simulation[key]
        return {"name": self.name, "vehicle": self.vehicle, "vehicle_parameters": self.vehicle_parameters,
                "thruster_time_constant": self.thruster_time_constant, "command": command,
                "controller": self.controller.describe(), "simulation": simulation}

    def replace(self, **changes: Any) -> Scenario:
        """A copy with some fields changed; the copy has its own config."""
        kept = {k: self.__dict__[k] for k in ("name", "description", "vehicle", "vehicle_parameters",
                                              "command", "controller", "source", "thruster_time_constant",
                                              "vehicle_file")}
        built = None if "simulation" in changes else self.__dict__.get("_built")
        return Scenario(**{**kept, "simulation": self.__dict__["simulation"], "_built": built, **changes})

    def with_controller(self, controller: ControllerSpec) -> Scenario:
        return self.replace(controller=controller)

    def __repr__(self) -> str:
        return f"Scenario(name={self.name!r}, vehicle={self.vehicle!r}, controller={self.controller.name!r})"

    def __getstate__(self) -> dict[str, Any]:
        return dict(self.__dict__)

    def __setstate__(self, state: dict[str, Any]) -> None:
        self.__dict__.update(state)

    def vehicle_data(self) -> VehicleFile:
        """The vehicle file, read and checked once: the copy the scenario holds
        while it still names the same file, else the file read now (and held)."""
        path, d = self.vehicle_path(), self.__dict__
        if self.vehicle_file is None or self.vehicle_file.path != path:
            d["vehicle_file"] = read_vehicle_file(path)
        density = d["simulation"].water_density
        held = d.get("_in_water")
        if held is None or held[0] is not self.vehicle_file or held[1] != density:
            d["_in_water"] = held = (self.vehicle_file, density, self.vehicle_file.in_water(density))
        return held[2]

    def vehicle_path(self) -> Path:
        return vehicle_path(self.vehicle, self.source)


def vehicle_path(vehicle: str, source: str = "") -> Path:
    """The vehicle file a scenario names: a preset's, or a ``.toml`` path
    (relative to the scenario file `source`, if any)."""
    p = Path(vehicle)
    if p.suffix == ".toml":
        return Path(source).parent / p if not p.is_absolute() and source else p
    return preset_path(vehicle)


SCENARIO_DIR = PACKAGE_DIR / "scenarios"
"""The shipped scenarios, each found by its name (the file's stem)."""


def shipped_scenarios() -> list[str]:
    """The names of the shipped scenarios (``paper_fig3``, ...)."""
    return sorted(p.stem for p in SCENARIO_DIR.glob("*.toml"))


def scenario_path(name_or_path: str | Path) -> Path:
    """The file to read for a scenario file's path or a shipped scenario's
    name (``paper_fig3``): the one resolver of ``neurov run``, the Gymnasium
    environment. A ``.toml`` path, a path through a folder (``./x``,
    ``/dev/zero``) or anything else that exists but a folder is taken as
    given (:func:`load_scenario` names what is wrong with it); another name
    must be a shipped scenario's (a folder of that name does not hide it),
    else :class:`ScenarioError` listing them."""
    return shipped_or_path(name_or_path, SCENARIO_DIR, "scenario", ScenarioError)
