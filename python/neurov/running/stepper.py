"""A scenario's run stepped from Python, one control period per call, with the
controller outside: the plant, reference model, thrusters, current,
disturbances, noise and faults of :func:`neurov.simulate`, and the same
:class:`Result` at the end."""

from __future__ import annotations

import time
from dataclasses import dataclass
from collections.abc import Callable
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from neurov import _core
from neurov.laws.protocol import ControllerCall
from neurov.results.timeseries import Result
from neurov.config.scenario import Scenario
from neurov.running.plant import build_vehicle, simulation_config

__all__ = ["Observation", "Simulator"]

Array = NDArray[np.float64]

_NAN6 = np.full(6, np.nan)


@dataclass(frozen=True)
class Observation:
    """What a controller is given at time t: the measured pose ``eta`` and body
    velocity ``nu`` (6,) (noise and sensor faults applied; NaN in a dropout)
    and the desired pose ``eta_d`` and its time derivatives ``eta_d_dot``,
    ``eta_d_ddot`` (6,), earth frame."""

    t: float
    eta: Array
    nu: Array
    eta_d: Array
    eta_d_dot: Array
    eta_d_ddot: Array

    @classmethod
    def _of(cls, o: _core.Observation) -> Observation:
        return cls(o.t, o.eta, o.nu, o.eta_d, o.eta_d_dot, o.eta_d_ddot)


class Simulator:
    """Everything of a scenario's run except the controller.

    >>> sim = Simulator(load_scenario("paper_fig3"))   # doctest: +SKIP
    >>> obs = sim.reset()
    >>> while not sim.done:
    ...     obs = sim.step(my_tau(obs))
    >>> sim.result().metrics()

    Each :meth:`step` logs the row at ``observation.t`` with the force tau and
    advances one control period (zero-order hold, RK4 substeps). `vehicle`
    replaces the scenario's plant (e.g. a perturbed one); `label` names the
    controller in the result; `log_rows` > 0 keeps at most that many rows
    (a long run handed over in chunks, see :meth:`run`).
    """

    def __init__(self, scenario: Scenario, *, vehicle: _core.Vehicle | None = None,
                 label: str = "python", log_rows: int = 0) -> None:
        if not isinstance(scenario, Scenario):
            raise TypeError(f"argument 'scenario' must be a neurov.Scenario, got {type(scenario).__name__}")
        self.scenario = scenario
        self.label = label
        plant = vehicle if vehicle is not None else build_vehicle(scenario)
        self._sim = _core.Simulator(plant, simulation_config(scenario), 0, log_rows)
        self._wall = 0.0
        self._errors: dict[str, dict[str, Any]] = {}

    def reset(self, seed: int | None = None) -> Observation:
        """Back to t = 0, noise drawn from `seed` (None: the last reset's seed,
        the scenario's at first, so the same run again); the first observation."""
        self._sim.reset(seed)
        self._wall = 0.0
        self._errors = {}
        return self.observation

    def step(self, tau: ArrayLike) -> Observation:
        """Applies `tau` (six finite numbers: body forces [N] and moments [N m])
        for one control period and returns the next observation. A `tau` of the
        wrong shape, type or with NaN/Inf raises ValueError/TypeError naming
        'tau'; after :attr:`done`, RuntimeError. Neither changes anything.
        The row's ``s`` (a controller's filtered tracking error) is NaN: not given."""
        start = time.perf_counter()
        self._sim.step(tau, _core.Status.ok, _NAN6)
        self._wall += time.perf_counter() - start
        return self.observation

    def run(self, controller: Any, on_rows: Callable[[dict[str, Any]], None] | None = None) -> Result:
        """Runs `controller` (a :class:`neurov.Controller`) from the current
        step to the end: its refused steps are logged with their status and
        the run goes on (a :class:`neurov.RefusedStepsWarning` at the end if
        the controller failed; ``result().first_refusal`` says how). Returns :meth:`result`. With `on_rows`, the rows are
        handed over as the simulator's log fills (``log_rows``) and at the
        end: ``on_rows(dict)`` gets the dict of ``neurov._core.run_closed_loop``
        for each chunk, and the result returned holds no rows."""
        call = ControllerCall(controller)
        call.reset()
        sim, step, observe, s_of = self._sim, self._sim.step, type(self._sim).observation.fget, call.s
        start = time.perf_counter()
        while not sim.done:
            if on_rows is not None and sim.log_full:
                on_rows(sim.drain())
            tau, status = call(observe(sim))
            s = s_of()
            step(tau, status, _NAN6 if s is None else s)
        if on_rows is not None:
            on_rows(sim.drain())
        self._wall += time.perf_counter() - start
        self._errors = call.errors
        call.warn_if_refused(self.label, self._sim.steps)
        return self.result()

    @property
    def observation(self) -> Observation:
        """What the controller is to be given now."""
        return Observation._of(self._sim.observation)

    @property
    def done(self) -> bool:
        """Every row of the scenario's duration simulated, or the plant diverged."""
        return self._sim.done

    @property
    def diverged(self) -> bool:
        return self._sim.diverged

    @property
    def steps(self) -> int:
        """Rows logged so far."""
        return self._sim.steps

    @property
    def state(self) -> tuple[Array, Array]:
        """The true (eta, nu) now, without noise or sensor faults."""
        return self._sim.state

    def result(self) -> Result:
        """The rows logged so far as a :class:`Result` (metrics, plots, export)."""
        raw = self._sim.result()
        diverged = bool(raw.pop("diverged"))
        extra = {"controller_errors": self._errors} if self._errors else {}
        return Result(scenario=self.scenario, controller=self.label, diverged=diverged,
                      wall_time=self._wall, extra=extra, **raw)
