"""The loop closed across the link: neurov's Simulator (plant, sensors,
disturbances, reference model) on the host, the controller on a board
(:class:`neurov.pil.board.Board`). Each control period the host sends the
measurement and the desired state, the board answers with tau, or with the
thrusts of its allocation (then tau = B u), and the host applies it."""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from numpy.typing import NDArray

from neurov.config.scenario import Scenario
from neurov.laws.registry import build_controller
from neurov.pil.board import Board
from neurov.pil.framing import NO_SEQ, STATUSES, Answer, PILError, Report, config_payload, measurement_payload
from neurov.results.timeseries import Result
from neurov.running.stepper import Simulator

__all__ = ["FAULT_KINDS", "LIMITS", "BoardController", "Flight", "board_parameters", "fly"]

Array = NDArray[np.float64]

#: Faults the host can inject into a step's frame: a NaN in x, x out of
#: range, a flipped byte (the CRC catches it), no frame at all.
FAULT_KINDS = ("nan", "range", "garble", "drop")
#: The board's range check, the largest magnitude of: the position x, y, z
#: [m]; roll and pitch [rad]; the linear velocity u, v, w [m/s]; the
#: angular velocity p, q, r [rad/s].
LIMITS = (1000.0, 1.5, 10.0, 10.0)
_MODIFICATIONS = {"none": 0, "sigma": 1, "e_modification": 2, "projection": 3}
_SATURATIONS = {"scale": 0, "clip": 1}


def board_parameters(scenario: Scenario) -> tuple[dict[str, Any], dict[str, Any] | None]:
    """The NN controller's parameters as the scenario's run builds them, and
    the thrusters' (matrix B (6, n), limits, saturation) or None."""
    spec = scenario.controller
    if getattr(spec, "type", None) != "nn":
        raise PILError(f"scenario {scenario.name!r}: processor in the loop flies the NN controller "
                       f"(controller.type = \"nn\"), not {getattr(spec, 'type', spec)!r}")
    c = build_controller(spec, scenario)
    cfg = c.config
    nn = {"centres": c.centres, "widths": c.widths, "input_offset": c.input_offset, "input_scale": c.input_scale,
          "lambda": cfg.lambda_, "kd": cfg.kd, "gamma": cfg.gamma, "dt": scenario.dt,
          "modification": _MODIFICATIONS[cfg.modification.name], "sigma_m": cfg.sigma_m, "kappa": cfg.kappa,
          "w_max": cfg.w_max, "dead_zone": cfg.dead_zone}
    sim = scenario.simulation
    if not sim.use_thrusters:
        return nn, None
    t = sim.thrusters
    if len(t.weights) and not np.allclose(t.weights, 1.0):
        raise PILError(f"scenario {scenario.name!r}: the board's allocation has no thruster weights")
    return nn, {"matrix": np.asarray(t.matrix), "min_thrust": t.min_thrust, "max_thrust": t.max_thrust,
                "saturation": _SATURATIONS[t.saturation.name]}


@dataclass
class Flight:
    """What the link saw, step by step: the board's ticks, status and fault
    per step, and each fault as an event (t, what the host did, what the
    board answered)."""

    ticks: list[int] = field(default_factory=list)
    status: list[int] = field(default_factory=list)
    fault: list[str] = field(default_factory=list)
    events: list[dict[str, Any]] = field(default_factory=list)
    counts: dict[str, int] = field(default_factory=dict)

    def count(self, name: str, t: float, injected: str | None = None) -> None:
        self.counts[name] = self.counts.get(name, 0) + 1
        self.events.append({"t": round(t, 9), "fault": name, "injected": injected})


class BoardController:
    """A :class:`neurov.Controller` whose step is the board's. `faults` maps
    a step index to one of :data:`FAULT_KINDS`; `timeout` [s] is how long
    the host waits for an answer before it counts the frame lost and applies
    zero force; `matrix` (6, n) turns the board's thrusts into tau."""

    def __init__(self, board: Board, matrix: Array | None, faults: dict[int, str], timeout: float) -> None:
        self.board, self.matrix, self.faults, self.timeout = board, matrix, faults, timeout
        self.flight = Flight()
        self.k = 0
        self.s: Array = np.full(6, np.nan)

    def step(self, eta: Array, nu: Array, eta_d: Array, eta_d_dot: Array, eta_d_ddot: Array, t: float = 0.0) -> Array:
        k, kind = self.k, self.faults.get(self.k)
        self.k += 1
        sent_eta = eta.copy()
        if kind == "nan":
            sent_eta[0] = math.nan
        elif kind == "range":
            sent_eta[0] = 10.0 * LIMITS[0]
        self.board.measure(measurement_payload(k, sent_eta, nu, eta_d, eta_d_dot, eta_d_ddot),
                           garble=kind == "garble", skip=kind == "drop")
        answer = self._answer(k, kind, t)
        f = self.flight
        if answer is None:
            f.ticks.append(0), f.status.append(-1), f.fault.append("lost")
            self.s = np.full(6, np.nan)
            return np.zeros(6)
        f.ticks.append(answer.ticks), f.status.append(answer.status), f.fault.append(answer.fault)
        if answer.status != 0:
            f.count(STATUSES.get(answer.status, f"status_{answer.status}"), t, kind)
        if answer.fault != "none":
            f.count(answer.fault, t, kind)
        self.s = answer.s if answer.fault == "none" else np.full(6, np.nan)
        return answer.tau if self.matrix is None else self.matrix @ answer.thrust

    def _answer(self, k: int, kind: str | None, t: float) -> Answer | None:
        """The board's answer to step k, or None when none came within the
        timeout; stale answers, and faults this step did not cause (a
        watchdog timeout while the host was busy), are counted and skipped."""
        deadline = time.monotonic() + self.timeout
        while (left := deadline - time.monotonic()) > 0:
            a = self.board.answer(left)
            if a is None:
                break
            if a.seq == k or (a.seq == NO_SEQ and kind in ("garble", "drop")):
                return a
            self.flight.count(f"unexpected_{a.fault}" if a.seq == NO_SEQ else "late", t, kind)
        self.flight.count("lost", t, kind)
        return None


def fly(scenario: Scenario, board: Board, *, faults: dict[int, str] | None = None, watchdog_ms: int = 1000,
        timeout: float = 10.0) -> tuple[Result, Flight, Report]:
    """Configures `board` for `scenario`'s NN controller and runs the
    scenario with it; the result (labelled with the board), what the link
    saw, and the board's report at the end."""
    nn, thrusters = board_parameters(scenario)
    n = int(np.asarray(nn["centres"]).shape[0])
    if n != board.hello.centres:
        raise PILError(f"scenario {scenario.name!r} has {n} centres, the image {board.hello.centres}: "
                       "build the image for this N (neurov pil builds it when --image is not given)")
    board.configure(config_payload(nn, thrusters, watchdog_ms, LIMITS))
    ctrl = BoardController(board, None if thrusters is None else thrusters["matrix"], faults or {},
                           timeout + watchdog_ms / 1000.0)
    sim = Simulator(scenario, label=f"nn (float) on {board.kind}")
    sim.reset()
    result = sim.run(ctrl)
    return result, ctrl.flight, board.report()
