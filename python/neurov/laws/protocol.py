"""What a controller written in Python is: the :class:`Controller` protocol,
and how one is called in a run (its refused steps named, the run going on)."""

from __future__ import annotations

from collections.abc import Mapping
import inspect
from typing import Any, Protocol, runtime_checkable

import numpy as np
from numpy.typing import ArrayLike, NDArray

from neurov import _core
from neurov.errors import RefusedStepsWarning

__all__ = ["BUILT_IN_CONTROLLERS", "OWN_FAILURES", "BatchedController", "Controller", "ControllerCall",
           "as_real_numbers", "describe_failures", "is_batched", "is_built_in", "own_failures",
           "require_controller"]

#: The compiled controllers (the C++ list, neurov._core.BUILT_IN_CONTROLLERS):
#: a run with one of these is the all-C++ loop.
BUILT_IN_CONTROLLERS: tuple[type, ...] = tuple(_core.BUILT_IN_CONTROLLERS.values())


@runtime_checkable
class Controller(Protocol):
    """A controller neurov can run: one method,

    ``step(eta, nu, eta_d, eta_d_dot, eta_d_ddot) -> tau``

    given the measured pose eta and body velocity nu (6,) (noise and sensor
    faults applied: NaN in a dropout) and the desired pose and its first two
    time derivatives (6,) in the earth frame, returns the body forces and
    moments tau: six finite numbers. If ``step`` also takes a keyword ``t``
    (or ``**kwargs``) it is given the time [s]. An optional ``reset()`` is
    called before each run; an optional attribute ``s`` (6,) is logged as the
    row's filtered tracking error.

    A step that raises (any ``Exception``), returns something that is not six
    numbers, or returns NaN/Inf is a refused step: the scenario's
    ``refused_step_policy`` decides the force, the row records the status
    (see :class:`ControllerCall`) and the run goes on.
    """

    def step(self, eta: NDArray[np.float64], nu: NDArray[np.float64], eta_d: NDArray[np.float64],
             eta_d_dot: NDArray[np.float64], eta_d_ddot: NDArray[np.float64]) -> ArrayLike: ...


@runtime_checkable
class BatchedController(Protocol):
    """A Python controller that steps K runs in one call: ``batched = True``
    and ``step_batch(eta, nu, eta_d, eta_d_dot, eta_d_ddot) -> tau``, each
    argument (K, 6) (row k is run k), tau (K, 6); a keyword ``t`` (K,), if
    taken, is given the times. K may be any size (a batch it fails on is run
    again run by run, K = 1). An optional ``reset()`` is called first."""

    batched: bool

    def step_batch(self, eta: NDArray[np.float64], nu: NDArray[np.float64], eta_d: NDArray[np.float64],
                   eta_d_dot: NDArray[np.float64], eta_d_ddot: NDArray[np.float64]) -> ArrayLike: ...


def is_batched(controller: Any) -> bool:
    """Whether `controller` declares itself batched (:class:`BatchedController`)."""
    return getattr(controller, "batched", False) is True and callable(getattr(controller, "step_batch", None))


def is_built_in(controller: Any) -> bool:
    """Whether `controller` is one of the compiled controllers of ``neurov._core``."""
    return isinstance(controller, BUILT_IN_CONTROLLERS)


def require_controller(controller: Any, what: str = "argument 'controller'") -> None:
    """TypeError naming `what` unless `controller` has a callable ``step``."""
    if not callable(getattr(controller, "step", None)):
        raise TypeError(f"{what} must be a controller spec or an object with a method "
                        f"step(eta, nu, eta_d, eta_d_dot, eta_d_ddot) -> tau, got {type(controller).__name__}")


def as_real_numbers(value: Any) -> NDArray[np.float64]:
    """`value` as a float64 array if it holds real numbers, by the rule of the
    compiled functions' arguments (python/bindings/numpy_args.hpp: a float,
    int or unsigned dtype, so not str, bool, complex or object); TypeError
    saying what it holds otherwise. Shape and finiteness are the caller's."""
    arr = np.asarray(value)
    if arr.dtype.kind not in "fiu":
        raise TypeError(f"{type(value).__name__} holding {arr.dtype} values, not real numbers")
    return arr.astype(np.float64, copy=False)


#: The refusals that are the controller's own failure (a dropout's
#: non_finite_input is the sensor's): a run with any is warned about, and
#: in a study it is a failed run.
OWN_FAILURES = ("invalid_argument", "non_finite_output")


def own_failures(errors: Mapping[str, Mapping[str, Any]]) -> dict[str, Mapping[str, Any]]:
    """The entries of a run's ``controller_errors`` (status name -> count,
    first time, first message) that are the controller's own failure."""
    return {k: e for k, e in errors.items() if k in OWN_FAILURES}


def describe_failures(own: Mapping[str, Mapping[str, Any]], rows: int) -> str:
    """``"3 of 15 steps refused, the first at t = 0.2 s (invalid_argument: ...)"``."""
    count = sum(int(e["count"]) for e in own.values())
    kind, first = min(own.items(), key=lambda kv: kv[1]["first_t"])
    return (f"{count} of {rows} steps refused, the first at t = {first['first_t']:g} s "
            f"({kind}: {first['first']})")


def takes_time(step: Any) -> bool:
    """Whether `step` accepts the keyword ``t``."""
    try:
        params = inspect.signature(step).parameters.values()
    except (TypeError, ValueError):  # a compiled method without a signature
        return False
    return any(p.name == "t" and p.kind in (p.POSITIONAL_OR_KEYWORD, p.KEYWORD_ONLY)
               or p.kind == p.VAR_KEYWORD for p in params)


class ControllerCall:
    """One controller called on an observation, its answer checked.

    Returns ``(tau, status)``: the status is ``ok`` with six finite numbers,
    else the refused step is named by a :class:`neurov.Status`:

    - ``non_finite_input``: step raised while the measurement held NaN/Inf
      (a dropout; the compiled controllers refuse such a step the same way);
    - ``invalid_argument``: step raised otherwise, or returned something that
      is not six real numbers (:func:`as_real_numbers`: str, bool, complex and
      object values are refused, as ``Simulator.step`` refuses them);
    - ``non_finite_output``: step returned NaN or Inf.

    The first message of each kind is kept in :attr:`errors` (for
    ``Result.extra["controller_errors"]``), with a count; a run the
    controller failed in is warned about (:meth:`warn_if_refused`).
    """

    def __init__(self, controller: Any) -> None:
        require_controller(controller)
        self.controller = controller
        self._step = controller.step
        self._with_t = takes_time(self._step)
        self._logs_s = hasattr(controller, "s")
        self.errors: dict[str, dict[str, Any]] = {}

    def reset(self) -> None:
        reset = getattr(self.controller, "reset", None)
        if callable(reset):
            reset()
        self.errors = {}

    def _refuse(self, status: Any, t: float, message: str) -> tuple[NDArray[np.float64], Any]:
        entry = self.errors.setdefault(status.name, {"count": 0, "first_t": t, "first": message})
        entry["count"] += 1
        return _NAN6, status

    def __call__(self, obs: _core.Observation) -> tuple[NDArray[np.float64], Any]:
        t, eta, nu = obs.t, obs.eta, obs.nu
        try:
            if self._with_t:
                out = self._step(eta, nu, obs.eta_d, obs.eta_d_dot, obs.eta_d_ddot, t=t)
            else:
                out = self._step(eta, nu, obs.eta_d, obs.eta_d_dot, obs.eta_d_ddot)
        except Exception as exc:  # a user's bug is a refused step; the run goes on
            measured = np.isfinite(eta).all() and np.isfinite(nu).all()
            status = _core.Status.invalid_argument if measured else _core.Status.non_finite_input
            return self._refuse(status, t, f"step raised {type(exc).__name__}: {exc}")
        try:
            tau = as_real_numbers(out)
        except Exception as exc:  # whatever converting it raised (a tensor's __array__): refused
            return self._refuse(_core.Status.invalid_argument, t,
                                f"step returned {type(out).__name__}, not six real numbers ({exc})")
        if tau.shape != (6,):
            return self._refuse(_core.Status.invalid_argument, t,
                                f"step returned shape {tau.shape}, expected (6,)")
        if not np.isfinite(tau).all():
            return self._refuse(_core.Status.non_finite_output, t, f"step returned {tau.tolist()}")
        return tau, _core.Status.ok

    def warn_if_refused(self, label: str, rows: int) -> None:
        """A :class:`neurov.RefusedStepsWarning` if the controller failed on
        any of the `rows` steps of a run (see :data:`OWN_FAILURES`)."""
        own = own_failures(self.errors)
        if not own:
            return
        import warnings

        warnings.warn(f"controller {label!r}: {describe_failures(own, rows)}; the run went on under "
                      "the scenario's refused_step_policy, see result.first_refusal",
                      RefusedStepsWarning, stacklevel=4)

    def s(self) -> NDArray[np.float64] | None:
        """The controller's ``s`` (6,) if it has one of that shape, else None."""
        if not self._logs_s:
            return None
        try:
            s = np.asarray(self.controller.s, dtype=np.float64)
        except (TypeError, ValueError):
            return None
        return s if s.shape == (6,) else None


_NAN6 = np.full(6, np.nan)
_NAN6.flags.writeable = False
