"""neurov's discrete-time parts as python-control systems, sampled at the
control period dt: a built-in controller, the reference model and the plant
with the force held over the period.

Each system's update function is the C++ step. python-control calls a
system's output and update functions as often as it needs (the output of
every subsystem several times per step while it resolves an interconnection's
feedthrough, and ``linearize`` or ``find_operating_point`` at points that are
not on any trajectory), so each call must be a pure function of (x, u). A
system therefore carries everything the C++ object remembers between steps in
its state vector, and each call restores a fresh object from that vector
(through the object's snapshot, the same one pickle uses), steps it and reads
the new memory back; the object the system was made from is never stepped.
"""

from __future__ import annotations

from collections import OrderedDict
from collections.abc import Callable
import math
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from neurov import _core
from neurov.control import INPUT_NAMES, STATE_NAMES, require_vehicle
from neurov.laws.protocol import BUILT_IN_CONTROLLERS, is_built_in

import control as ct

__all__ = ["COMMAND_NAMES", "DESIRED_NAMES", "controller_system", "reference_system", "sampled_plant"]

Array = NDArray[np.float64]

_POSE = STATE_NAMES[:6]
#: The desired state the reference model gives the controller: eta_d, then
#: its first and second time derivatives (earth frame).
DESIRED_NAMES = (tuple(f"{n}_d" for n in _POSE) + tuple(f"{n}_d_dot" for n in _POSE)
                 + tuple(f"{n}_d_ddot" for n in _POSE))
#: The commanded pose r the reference model follows.
COMMAND_NAMES = tuple(f"{n}_cmd" for n in _POSE)

# The snapshot fields a controller's next steps depend on (the rest of its
# snapshot is its configuration or the diagnostics of the last step, which
# the step recomputes). The NN's weight norm is carried as accumulated by its
# updates, as its own snapshot does, so that a restored controller steps
# bit for bit as the original. A built-in controller not named here carries
# every numeric field of its snapshot: correct, only a longer state.
_MEMORY: dict[str, tuple[str, ...]] = {
    "NNAdaptiveController": ("weights", "weight_norm"),
    "LinearAdaptiveController": ("theta",),
    "PIDController": ("integral",),
    "PDController": (),
    "SlidingModeController": (),
    "ComputedTorqueController": (),
    "ArduSubController": ("memory",),
}
_REFERENCE_MEMORY = ("eta_d", "nu_d", "desired_eta_d", "desired_eta_d_dot", "desired_eta_d_ddot",
                     "pitch_limited")


def _period(dt: Any, what: str = "argument 'dt'") -> float:
    """dt as a float > 0 (the control period); ValueError naming `what`."""
    if isinstance(dt, bool) or not isinstance(dt, (int, float, np.integer, np.floating)):
        raise TypeError(f"{what} (the control period [s]) must be a number, got {type(dt).__name__}")
    value = float(dt)
    if not (math.isfinite(value) and value > 0.0):
        raise ValueError(f"{what} (the control period [s]) must be finite and > 0, got {value!r}")
    return value


class _Snapshot:
    """An object's remembered fields <-> a flat state vector: `fields` of its
    pickle snapshot, in order, each raveled."""

    def __init__(self, obj: Any, fields: tuple[str, ...] | None) -> None:
        self.cls: Any = type(obj)
        self.template = obj.__getstate__()
        if fields is None:  # every numeric field but the configuration
            fields = tuple(k for k, v in self.template.items()
                           if k != "config" and isinstance(v, (float, int, bool, np.ndarray)))
        self.fields = fields
        self.shapes = [np.shape(self.template[f]) for f in fields]
        self.kinds = [type(self.template[f]) for f in fields]
        self.sizes = [int(np.prod(s)) for s in self.shapes]

    def labels(self) -> list[str]:
        """The states' names: the field's, with the flat index for an array."""
        out: list[str] = []
        for f, n in zip(self.fields, self.sizes):
            out += [f] if n == 1 else [f"{f}[{i}]" for i in range(n)]
        return out

    def vector(self, state: dict[str, Any] | None = None) -> Array:
        state = self.template if state is None else state
        if not self.fields:
            return np.zeros(0)
        return np.concatenate([np.ravel(np.asarray(state[f], dtype=np.float64)) for f in self.fields])

    def restore(self, x: Array) -> Any:
        state = dict(self.template)
        i = 0
        for f, shape, kind, n in zip(self.fields, self.shapes, self.kinds, self.sizes):
            part = x[i:i + n]
            if kind is bool:  # a flag: python-control may perturb it (linearize)
                state[f] = bool(part[0] >= 0.5)
            elif kind is int:
                state[f] = int(round(part[0]))
            elif kind is float:
                state[f] = float(part[0])
            else:
                state[f] = part.reshape(shape).copy()
            i += n
        obj = self.cls.__new__(self.cls)
        obj.__setstate__(state)
        return obj


class _Memo:
    """The last few results of a pure step function of (x, u), so that the
    repeated calls python-control makes at one point cost one C++ step."""

    def __init__(self, step: Callable[[Array, Array], tuple[Array, Array]], size: int = 8) -> None:
        self.step, self.size = step, size
        self.cache: OrderedDict[tuple[bytes, bytes], tuple[Array, Array]] = OrderedDict()

    def __call__(self, x: Array, u: Array) -> tuple[Array, Array]:
        x = np.asarray(x, dtype=np.float64)
        u = np.asarray(u, dtype=np.float64)
        key = (x.tobytes(), u.tobytes())
        hit = self.cache.get(key)
        if hit is None:
            hit = self.step(x, u)
            self.cache[key] = hit
            if len(self.cache) > self.size:
                self.cache.popitem(last=False)
        return hit


def _attach_x0(sys: ct.NonlinearIOSystem, x0: Array) -> ct.NonlinearIOSystem:
    # python-control systems have no initial state; neurov.control.initial_state reads this.
    sys.x0 = np.array(x0, dtype=np.float64)
    return sys


def controller_system(controller: Any, dt: float, *, name: str = "controller") -> ct.NonlinearIOSystem:
    """A built-in controller (``neurov.NNAdaptiveController``, ...) as a
    discrete-time ``control.NonlinearIOSystem`` with sampling time `dt`.

    Inputs: the measured pose and velocity (named as the plant's outputs,
    ``x ... r``) and the desired state (:data:`DESIRED_NAMES`); outputs: the
    force tau (``tau_X ... tau_N``), which depends on the inputs of the same
    step (the controller's step is a direct feedthrough). States: what the
    controller remembers (the NN's weights W and their norm, the linear
    adaptive controller's theta_hat, the PID's integral; none for PD, sliding
    mode and computed torque), starting from the state `controller` is in,
    which is copied and never stepped. The system's ``x0`` is that state.

    A step the controller refuses (a NaN input, the pitch singularity) raises
    ValueError: python-control's simulation has no refused-step policy.
    """
    if not is_built_in(controller):
        names = ", ".join(c.__name__ for c in BUILT_IN_CONTROLLERS)
        raise TypeError(f"argument 'controller' must be a built-in controller ({names}), "
                        f"got {type(controller).__name__}")
    period = _period(dt)
    own = getattr(controller.config, "dt", None)
    if own is not None and not math.isclose(period, own, rel_tol=1e-12, abs_tol=0.0):
        raise ValueError(f"argument 'dt' ({period!r} s) must be the controller's control period, "
                         f"{type(controller).__name__}.config.dt = {own!r} s")
    memory = _Snapshot(controller, _MEMORY.get(type(controller).__name__))

    def step(x: Array, u: Array) -> tuple[Array, Array]:
        c = memory.restore(x)
        try:
            tau = c.step(u[:6], u[6:12], u[12:18], u[18:24], u[24:30])
        except ValueError as exc:
            raise ValueError(f"{name}: {exc}") from exc
        return np.asarray(tau, dtype=np.float64), memory.vector(c.__getstate__())

    memo = _Memo(step)
    sys = ct.NonlinearIOSystem(
        lambda t, x, u, params: memo(x, u)[1], lambda t, x, u, params: memo(x, u)[0],
        inputs=list(STATE_NAMES + DESIRED_NAMES), outputs=list(INPUT_NAMES),
        states=memory.labels(), dt=period, name=name)
    return _attach_x0(sys, memory.vector())


def reference_system(reference: _core.ReferenceModel, dt: float, *,
                     name: str = "reference") -> ct.NonlinearIOSystem:
    """The reference model (``neurov.ReferenceModel``) as a discrete-time
    ``control.NonlinearIOSystem`` with sampling time `dt`: input the
    commanded pose r (:data:`COMMAND_NAMES`, held over the period), outputs
    the desired state of :data:`DESIRED_NAMES` that the last step gave (at
    rest at its initial pose before the first), so the output at t_k does not
    depend on the input at t_k, as in neurov's loop. States: eta_d, nu_d, the
    desired state and the pitch-limit flag (its snapshot), starting from the
    state `reference` is in (``x0``); `reference` is never stepped.
    """
    if not isinstance(reference, _core.ReferenceModel):
        raise TypeError(f"argument 'reference' must be a neurov.ReferenceModel, got {type(reference).__name__}")
    period = _period(dt)
    memory = _Snapshot(reference, _REFERENCE_MEMORY)
    desired = slice(12, 30)  # desired_eta_d, _dot, _ddot in the state

    def step(x: Array, u: Array) -> tuple[Array, Array]:
        r = memory.restore(x)
        try:
            r.step(u, period)
        except ValueError as exc:
            raise ValueError(f"{name}: {exc}") from exc
        return x[desired], memory.vector(r.__getstate__())

    memo = _Memo(step)
    sys = ct.NonlinearIOSystem(
        lambda t, x, u, params: memo(x, u)[1], lambda t, x, u, params: np.asarray(x)[desired],
        inputs=list(COMMAND_NAMES), outputs=list(DESIRED_NAMES), states=memory.labels(),
        dt=period, name=name)
    return _attach_x0(sys, memory.vector())


def sampled_plant(vehicle: _core.Vehicle, dt: float, substeps: int = 10, current: ArrayLike | None = None,
                  *, x0: ArrayLike | None = None, name: str = "plant") -> ct.NonlinearIOSystem:
    """The plant sampled at the control period: a discrete-time
    ``control.NonlinearIOSystem`` whose update advances (eta, nu) by `dt`
    with the input tau held, in `substeps` RK4 steps of dt / substeps (C++
    :func:`neurov._core.rk4_step`, the integrator and step of
    :func:`neurov.simulate`). States and outputs: eta then nu
    (:data:`neurov.control.STATE_NAMES`); inputs: tau. `current` (3,) is a
    constant NED current [m/s]; `x0` (12,) the initial (eta, nu), default
    rest at the origin (the system's ``x0``).

    A step that leaves the model's range (the pitch singularity, an
    overflow) raises ValueError, where neurov.simulate ends the run as
    diverged.
    """
    require_vehicle(vehicle)
    period = _period(dt)
    if isinstance(substeps, bool) or not isinstance(substeps, (int, np.integer)) \
            or not 1 <= substeps <= _core.MAX_SUBSTEPS:
        raise ValueError(f"argument 'substeps' must be a whole number in 1..{_core.MAX_SUBSTEPS}, got {substeps!r}")
    n = int(substeps)
    h = period / n  # as the C++ loop computes its substep
    c = None if current is None else np.array(current, dtype=np.float64)
    zeros = np.zeros(6)
    _core.plant_derivative(vehicle, zeros, zeros, zeros, c)  # the C++ names a bad current
    start = np.zeros(12) if x0 is None else np.array(x0, dtype=np.float64)
    if start.shape != (12,) or not np.all(np.isfinite(start)):
        raise ValueError(f"argument 'x0' must be 12 finite numbers (eta, nu), got shape {start.shape}")

    def update(t: float, x: Array, u: Array, params: dict[str, Any]) -> Array:
        eta, nu = x[:6], x[6:]
        try:
            for _ in range(n):
                eta, nu = _core.rk4_step(vehicle, eta, nu, u, h, c)
        except ValueError as exc:
            raise ValueError(f"{name}, the step from t = {t!r} s: {exc}") from exc
        return np.concatenate([eta, nu])

    sys = ct.NonlinearIOSystem(update, None, inputs=list(INPUT_NAMES), outputs=list(STATE_NAMES),
                               states=list(STATE_NAMES), dt=period, name=name)
    return _attach_x0(sys, start)
