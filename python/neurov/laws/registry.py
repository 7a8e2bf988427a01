"""The controller registry: type name -> config class, Python options, builder.

One entry per controller, used by the scenario reader, :func:`neurov.simulate`,
studies and the command line. A controller's gains are its C++ config struct
(``neurov._core.PDConfig`` ...), with the C++ defaults and validator; an
entry adds only what the core cannot know: the fields the builder fills from
the scenario (the control period, the nominal model) and options that are
Python's work (the NN centres' placement). The entries come from
``neurov._core.BUILT_IN_CONTROLLERS``, the C++ list of built-in controllers:
adding one there adds it here.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from typing import Any, Protocol

import numpy as np
from numpy.typing import NDArray

from neurov import _core
from neurov.laws import centres as centre_placement
from neurov.laws.path_centres import along_path
from neurov.schema import field_names


__all__ = ["ControllerType", "REGISTRY", "build_controller", "default_centre_box", "input_normalisation", "make_centres",
           "register"]

Array = NDArray[np.float64]


class SpecLike(Protocol):
    """What a builder reads of a controller spec (the configuration layer's
    :class:`neurov.config.scenario.ControllerSpec`, above this one): its
    ``type``, ``label``, ``options`` and bound ``config``, and the options
    and config fields by name (``spec.width``, ``spec.kd``)."""

    type: str
    label: str
    options: dict[str, Any]
    config: Any

    def __getattr__(self, name: str) -> Any: ...


class ScenarioLike(Protocol):
    """What a builder reads of a scenario (:class:`neurov.config.scenario.Scenario`,
    above this one): its vehicle file (``vehicle_data()``), and its
    ``name``, ``command``, ``simulation`` and config fields (``dt``, ``eta0``) by name."""

    def vehicle_data(self) -> Any: ...

    def __getattr__(self, name: str) -> Any: ...


@dataclass(frozen=True)
class ControllerType:
    """One kind of controller.

    name: the scenario file's ``type``; title: its name in tables and plots;
    config: the bound C++ config class; build: (spec, scenario) -> controller;
    managed: config fields the builder fills from the scenario (not read from
    files); options: Python-level options and their defaults; keys: TOML key
    -> config field where the two differ.
    """

    name: str
    title: str
    config: type
    build: Callable[[SpecLike, ScenarioLike], Any]
    managed: tuple[str, ...] = ()
    options: Mapping[str, Any] = field(default_factory=dict)
    keys: Mapping[str, str] = field(default_factory=dict)

    def fields(self) -> list[str]:
        """The config fields a file may set (TOML names)."""
        inverse = {v: k for k, v in self.keys.items()}
        return [inverse.get(f, f) for f in field_names(self.config()) if f not in self.managed]


REGISTRY: dict[str, ControllerType] = {}


def register(kind: ControllerType) -> ControllerType:
    """Adds (or replaces) a controller type."""
    REGISTRY[kind.name] = kind
    return kind


def build_controller(spec: SpecLike, scenario: ScenarioLike) -> Any:
    """A fresh controller from its spec, for the scenario's control period and
    nominal vehicle (the vehicle file without the scenario's parameter
    overrides: a controller is designed for the vehicle as documented, not
    the plant as perturbed)."""
    try:
        kind = REGISTRY[spec.type]
    except KeyError:
        raise ValueError(f"controller.type must be one of {sorted(REGISTRY)}, got {spec.type!r}") from None
    return kind.build(spec, scenario)


def default_centre_box(scenario: ScenarioLike) -> tuple[Array, Array]:
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


def make_centres(spec: SpecLike, low: Array, high: Array, scenario: ScenarioLike | None = None) -> Array:
    """The (N, 24) centres a controller spec asks for; `low`/`high` is the box
    used when the spec gives none; `scenario` the run's, for centres along
    its commanded path (``method = "path"``)."""
    c = spec.centres
    if isinstance(c, np.ndarray):
        return np.asarray(c, dtype=np.float64)
    method = c.get("method", "sobol")
    if method == "grid":
        return centre_placement.grid(c["axes"])
    if method == "path":
        if scenario is None:
            raise ValueError("centres.method 'path' places the centres on a scenario's path: give the scenario")
        centres = along_path(scenario, int(c.get("n", 64)), seed=int(c.get("seed", 0)))
        if spec.options.get("inputs") == "normalised":
            offset, scale = input_normalisation(scenario)
            centres = (centres - offset) * scale
        return centres
    if spec.options.get("inputs") == "normalised":
        # The network sees x_hat, in which the scenario's box is [-1, 1]^24.
        low, high = np.full(24, -1.0), np.full(24, 1.0)
    lo = low if c.get("low") is None else np.asarray(c["low"], dtype=np.float64)
    hi = high if c.get("high") is None else np.asarray(c["high"], dtype=np.float64)
    fn = centre_placement.sobol if method == "sobol" else centre_placement.latin_hypercube
    return fn(int(c.get("n", 64)), lo, hi, seed=int(c.get("seed", 0)))


def _configured(spec: SpecLike, **managed: Any) -> Any:
    """A copy of the spec's config with the managed fields set."""
    import copy

    config = copy.copy(spec.config)
    for name, value in managed.items():
        setattr(config, name, value)
    return config


def _nominal(scenario: ScenarioLike) -> Any:
    return scenario.vehicle_data().vehicle()


def input_normalisation(scenario: ScenarioLike) -> tuple[Array, Array]:
    """The NN's input offset and scale with ``inputs = "normalised"``:
    x_hat = (x - offset) * scale maps the scenario's centre box
    (:func:`default_centre_box`) onto [-1, 1]^24, so that one width suits
    positions, angles, velocities and accelerations alike."""
    low, high = default_centre_box(scenario)
    return (low + high) / 2.0, 2.0 / (high - low)


def _build_nn(spec: SpecLike, scenario: ScenarioLike) -> Any:
    centres = make_centres(spec, *default_centre_box(scenario), scenario)
    if spec.options.get("inputs") == "normalised":
        network = _core.RbfNetwork(centres, spec.width, *input_normalisation(scenario))
    else:
        network = _core.RbfNetwork(centres, spec.width)
    return _core.NNAdaptiveController(network, _configured(spec, dt=scenario.dt))


def _build_linear(spec: SpecLike, scenario: ScenarioLike) -> Any:
    theta0 = np.zeros(len(_core.THETA_NAMES))
    if spec.theta0 in ("true", "scaled"):
        theta0 = _core.regressor_parameters(_nominal(scenario))
        if spec.theta0 == "scaled":
            theta0 = theta0 * spec.theta0_scale
    return _core.LinearAdaptiveController(_configured(spec, dt=scenario.dt, theta0=theta0))


def _build_from_config(cls: type) -> Callable[[SpecLike, ScenarioLike], Any]:
    """The builder of a controller whose managed fields are only those the
    scenario always fills (:data:`_FROM_SCENARIO`)."""

    def build(spec: SpecLike, scenario: ScenarioLike) -> Any:
        fill = {name: value(scenario) for name, value in _FROM_SCENARIO.items() if hasattr(spec.config, name)}
        return cls(_configured(spec, **fill))

    return build


def _build_ardusub(spec: SpecLike, scenario: ScenarioLike) -> Any:
    """ArduSub for the scenario's control period, with the ESC thrust table
    of the vehicle's thruster curve (16 PWMs over its range, at its supply
    voltage); the frame must have the vehicle's number of thrusters."""
    fill: dict[str, Any] = {"dt": scenario.dt}
    thrusters = scenario.vehicle_data().thrusters
    if thrusters is not None:
        frame = int(spec.config.FRAME_CONFIG)
        motors = 8 if frame == 2 else 6
        have = int(np.asarray(thrusters["matrix"]).shape[1])
        if have != motors:
            raise ValueError(f"controller.FRAME_CONFIG = {frame} ({motors} motors) does not fit the vehicle's "
                             f"{have} thrusters: set FRAME_CONFIG = {2 if have == 8 else 1} "
                             "(2: vectored 6DOF, BlueROV2 Heavy; 1: vectored, BlueROV2)")
        curves = thrusters.get("curves")
        if curves:
            c = curves[0]
            pwm = np.linspace(float(c.table[0, 0]), float(c.table[-1, 0]), 16)
            thrust = np.array([c.static_thrust(p, thrusters["supply_voltage"]) for p in pwm])
            fill.update(curve_pwm=pwm, curve_thrust=thrust, curve_rows=16.0)
    return _core.ArduSubController(_configured(spec, **fill))


#: The config fields a builder fills from the scenario, by name: the
#: control period, and the nominal model as theta or as a Vehicle.
_FROM_SCENARIO: dict[str, Callable[[ScenarioLike], Any]] = {
    "dt": lambda scenario: scenario.dt,
    "theta": lambda scenario: _core.regressor_parameters(_nominal(scenario)),
    "vehicle": _nominal,
}

#: What a controller adds to its C++ class in Python: options and the
#: builder that reads them (every other built-in controller is built from its
#: config alone).
_PYTHON_LEVEL: dict[str, dict[str, Any]] = {
    "nn": {"build": _build_nn, "managed": ("dt",),
           "options": {"width": 30.0, "centres": {"method": "sobol", "n": 64}, "inputs": "si"}},
    "ardusub": {"build": _build_ardusub, "managed": ("dt", "mode", "curve_pwm", "curve_thrust", "curve_rows"),
                "options": {"params": ""}},
    "linear": {"build": _build_linear, "managed": ("dt", "theta0"),
               "options": {"theta0": "zero", "theta0_scale": 1.0}},
}


def _register_built_ins() -> None:
    """One entry per compiled controller, in the order of the C++ list
    (neurov/control/built_in_controllers.hpp)."""
    for name, cls in _core.BUILT_IN_CONTROLLERS.items():
        fields = set(dir(cls.Config))
        extra = _PYTHON_LEVEL.get(name, {})
        register(ControllerType(
            name, cls.title, cls.Config, extra.get("build", _build_from_config(cls)),
            managed=extra.get("managed", tuple(f for f in _FROM_SCENARIO if f in fields)),
            options=extra.get("options", {}),
            keys={"lambda": "lambda_"} if "lambda_" in fields else {}))


_register_built_ins()
