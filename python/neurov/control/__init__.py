"""neurov in python-control's shapes (the extra ``neurov[control]``).

- :func:`nonlinear_system`: the 12-state plant as a
  ``control.NonlinearIOSystem`` whose update function is neurov's C++
  dynamics (:func:`neurov._core.plant_derivative`).
- :func:`linearize`: the plant's linear model about a point as a
  ``control.StateSpace``, from the analytic Jacobians computed in C++
  (:func:`neurov._core.plant_jacobians`), not from finite differences.
- :func:`to_time_response`: a closed-loop run (:class:`neurov.Result`) as
  ``control.TimeResponseData``, so ``control.step_info`` and python-control's
  plots work on it.
- :mod:`neurov.control.sampled` and :mod:`neurov.control.loop`: a built-in
  controller, the reference model and the plant sampled at the control
  period as discrete-time systems whose updates are the C++ steps, and a
  scenario's closed loop joined by ``control.interconnect`` (see
  ``docs/control.md``).

States are eta (NED position, ZYX Euler angles) then nu (body velocities);
inputs are the generalised forces tau; every signal is named, so
``sys.find_state("theta")`` and ``response.outputs[sys.find_output("z")]``
work.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import ArrayLike

from neurov import _core

try:
    import control as ct
except ImportError as exc:  # pragma: no cover - depends on the environment
    raise ImportError(
        "neurov.control needs python-control (>= 0.10): pip install 'neurov[control]'"
    ) from exc

if TYPE_CHECKING:
    from neurov.results.timeseries import Result

__all__ = [
    "COMMAND_NAMES",
    "DESIRED_NAMES",
    "INPUT_NAMES",
    "STATE_NAMES",
    "closed_loop",
    "command_input",
    "controller_system",
    "initial_state",
    "linearize",
    "nonlinear_system",
    "reference_system",
    "sampled_plant",
    "scenario_systems",
    "simulate",
    "time_grid",
    "to_time_response",
    "unsupported_features",
]

#: eta (x, y, z [m]; phi, theta, psi [rad]) then nu (u, v, w [m/s]; p, q, r [rad/s]).
STATE_NAMES: tuple[str, ...] = ("x", "y", "z", "phi", "theta", "psi", "u", "v", "w", "p", "q", "r")
#: tau: forces [N] along and moments [N m] about the body axes.
INPUT_NAMES: tuple[str, ...] = ("tau_X", "tau_Y", "tau_Z", "tau_K", "tau_M", "tau_N")


def require_vehicle(vehicle: Any) -> None:
    if not isinstance(vehicle, _core.Vehicle):
        raise TypeError(f"argument 'vehicle' must be a neurov.Vehicle, got {type(vehicle).__name__}")


def nonlinear_system(vehicle: _core.Vehicle, current: ArrayLike | None = None,
                     *, name: str | None = None) -> ct.NonlinearIOSystem:
    """The plant eta_dot = J(eta) nu, M nu_dot + C nu + D nu + g = tau as a
    continuous-time ``control.NonlinearIOSystem``: 12 states (eta, nu), the 6
    inputs tau, outputs the states. ``current`` (3,) is a constant NED current
    velocity [m/s]; the hydrodynamic terms then use the relative velocity.

    The update function raises ``ValueError`` if a simulation reaches the
    pitch singularity (cos(theta) = 0), where the Euler angles are undefined.
    """
    require_vehicle(vehicle)
    zeros = np.zeros(6)
    # The C++ checks current (shape, finiteness) and names it in the error.
    _core.plant_derivative(vehicle, zeros, zeros, zeros, current)
    c = None if current is None else np.array(current, dtype=float)

    def update(t: float, x: np.ndarray, u: np.ndarray, params: dict[str, Any]) -> np.ndarray:
        return _core.plant_derivative(vehicle, x[:6], x[6:], u, c)

    return ct.NonlinearIOSystem(update, None, inputs=list(INPUT_NAMES), outputs=list(STATE_NAMES),
                                states=list(STATE_NAMES), name=name)


def linearize(vehicle: _core.Vehicle, eta0: ArrayLike, nu0: ArrayLike,
              tau0: ArrayLike | None = None, current: ArrayLike | None = None,
              *, name: str | None = None) -> ct.StateSpace:
    """The linear model about (eta0, nu0, tau0) as a ``control.StateSpace``
    in deviation variables: with x = (eta, nu),
    d(x - x0)/dt = A (x - x0) + B (tau - tau0), y = x - x0.

    A and B are the analytic Jacobians of the C++ dynamics. The plant is
    affine in tau, so tau0 (default zero) changes neither; it is checked and
    kept in the call so that it reads as the operating point it is. Unless
    (eta0, nu0, tau0) is an equilibrium (e.g. at rest with tau0 = g(eta0)),
    the linear model leaves out the constant drift f(x0, tau0).
    """
    require_vehicle(vehicle)
    a, b = _core.plant_jacobians(vehicle, eta0, nu0, tau0, current)
    return ct.ss(a, b, np.eye(12), np.zeros((12, 6)), inputs=list(INPUT_NAMES),
                 outputs=list(STATE_NAMES), states=list(STATE_NAMES), name=name)


def to_time_response(result: Result) -> ct.TimeResponseData:
    """A run as ``control.TimeResponseData``: time t_k = k dt, outputs and
    states (eta, nu) and inputs the force the thrusters applied
    (``result.tau_applied``; the scenario's disturbance is not an input).

    ``control.step_info(resp.outputs[2], resp.time)`` gives the heave step's
    rise time, overshoot and settling time; ``resp.plot()`` draws it.
    """
    if not is_result(result):
        raise TypeError(f"argument 'result' must be a neurov.Result, got {type(result).__name__}")
    states = np.hstack([result.eta, result.nu]).T
    return ct.TimeResponseData(
        result.t, states, states=states, inputs=result.tau_applied.T,
        output_labels=list(STATE_NAMES), state_labels=list(STATE_NAMES),
        input_labels=list(INPUT_NAMES), sysname=f"{result.scenario.name} ({result.controller})",
        title=f"{result.scenario.name}, {result.controller} controller")


# The discrete-time parts; imported last, as they use the names above.
from neurov.control.sampled import (  # noqa: E402
    COMMAND_NAMES, DESIRED_NAMES, controller_system, reference_system, sampled_plant)
from neurov.control.loop import (  # noqa: E402
    closed_loop, command_input, initial_state, scenario_systems, simulate, time_grid, unsupported_features)
from neurov.results.columns import is_result
