"""The tracking task's arithmetic over K runs at once: the action's scale,
the observation, the reward and the episode's end. The single environment
(:class:`neurov.gym.TrackingEnv`, K = 1) and the vector one
(:class:`neurov.gym.TrackingVectorEnv`) both compute them here, so lane i of
the vector env is the single env to the last bit (docs/gymnasium.md)."""

from __future__ import annotations

from pathlib import Path

import numpy as np
from gymnasium import spaces
from numpy.typing import NDArray

from neurov import _core
from neurov.gym.limits import single_dof_limits
from neurov.config.reading import load_scenario
from neurov.config.scenario import Scenario, ScenarioError, scenario_path
from neurov.config.vehicle_file import VehicleFile, read_vehicle_file

__all__ = ["TrackingTask", "resolve_scenario", "wrap"]

Array = NDArray[np.float64]


def resolve_scenario(scenario: Scenario | str | Path) -> Scenario:
    """A Scenario as given, a scenario file by path, or a shipped scenario by
    name (:func:`neurov.config.scenario.scenario_path`)."""
    if isinstance(scenario, Scenario):
        return scenario
    if not isinstance(scenario, (str, Path)):
        raise TypeError(f"argument 'scenario' must be a Scenario, a shipped scenario's name or a path, "
                        f"got {type(scenario).__name__}")
    try:
        path = scenario_path(scenario)
    except ScenarioError as e:
        raise ValueError(f"argument 'scenario': {e}") from None
    return load_scenario(path)


def _vehicle_file(scenario: Scenario) -> VehicleFile:
    """The vehicle file the scenario read, or read now (a scenario object
    that does not keep one)."""
    vehicle_data = getattr(scenario, "vehicle_data", None)
    if vehicle_data is not None:
        return vehicle_data()
    return read_vehicle_file(scenario.vehicle_path())


def wrap(angle: Array, out: Array | None = None, scratch: Array | None = None) -> Array:
    """The angles in [-pi, pi] (the nearest multiple of 2 pi taken off),
    into `out` (which may be `angle`) with `scratch` (angle's shape) if given:
    on a step's tiny arrays, allocation costs as much as the arithmetic."""
    turns = np.divide(angle, 2.0 * np.pi, out=scratch)
    np.rint(turns, out=turns)
    np.multiply(turns, 2.0 * np.pi, out=turns)
    return np.subtract(angle, turns, out=out)


class _Scratch:
    """Buffers for K rows, reused by every step (never returned to a caller).
    The two angle errors sit side by side so that a step wraps them in one
    pass over contiguous memory (on a (1, 6) array, four numpy calls cost
    half what they do on a strided view), next to what the reward squares."""

    def __init__(self, k: int, n: int) -> None:
        self.earth = np.empty((k, 3, 6))  # the rows to_body turns: eta - eta_d, eta_d_dot, eta_d_ddot
        self.error, self.rate, self.accel = self.earth[:, 0], self.earth[:, 1], self.earth[:, 2]
        self.error_angles = self.earth[:, 0, 3:]
        # Measured angle error, then what the reward squares: true angle error, true position error, action.
        self.errors = np.empty((k, 9 + n))
        self.angles, self.both_angles, self.scored = self.errors[:, :3], self.errors[:, :6], self.errors[:, 3:]
        self.true_angles, self.true_position, self.action = (self.errors[:, 3:6], self.errors[:, 6:9],
                                                             self.errors[:, 9:])
        self.turns = np.empty((k, 6))
        self.offset = np.empty((k, 3))  # |p - box centre|


class TrackingTask:
    """What the environment adds to a scenario's run, for K rows at a time:
    the spaces, the normalised action's force, the observation, the reward,
    termination and truncation. The arguments are those of TrackingEnv
    (validated here, once)."""

    def __init__(self, scenario: Scenario, config: _core.SimulationConfig, action: str = "body", *,
                 position_weight: float = 1.0, attitude_weight: float = 1.0, effort_weight: float = 0.01,
                 box_margin: float = 5.0, velocity_bound: float = 5.0) -> None:
        if action not in ("body", "thrusters"):
            raise ValueError(f"argument 'action' must be 'body' or 'thrusters', got {action!r}")
        for name, v in (("position_weight", position_weight), ("attitude_weight", attitude_weight),
                        ("effort_weight", effort_weight)):
            if not (np.isfinite(v) and v >= 0):
                raise ValueError(f"argument {name!r} must be a finite number >= 0, got {v!r}")
        for name, v in (("box_margin", box_margin), ("velocity_bound", velocity_bound)):
            if not (np.isfinite(v) and v > 0):
                raise ValueError(f"argument {name!r} must be a finite number > 0, got {v!r}")
        self.scenario = scenario
        self.action_kind = action
        self.weights = (float(position_weight), float(attitude_weight), float(effort_weight))
        self.check_faults = len(config.sensor_faults) > 0
        self._set_action_scale(action)
        # The reward's weights on the squares of (pose error, action).
        # The reward's weights on the squares of (angle error, position error, action); negated: x @ -w
        # is -(x @ w) to the bit, one call fewer.
        self._neg_square_weights = -np.repeat(self.weights[1::-1] + self.weights[2:], (3, 3, self.action_shape[0]))
        self._scratch: dict[int, _Scratch] = {}

        poses = np.asarray(config.command.poses)
        corners = np.vstack([poses[:, :3], np.asarray(config.eta0)[:3]])
        self.box_low = corners.min(axis=0) - box_margin
        self.box_high = corners.max(axis=0) + box_margin
        self._box_centre = (self.box_low + self.box_high) / 2
        self._box_half = (self.box_high - self.box_low) / 2
        self._ones = np.ones(3, dtype=bool)
        reach = float(np.linalg.norm(self.box_high - self.box_low))
        self.termination_cost = float(position_weight) * reach**2
        high = np.concatenate([np.full(3, reach), np.full(3, np.pi), np.full(18, velocity_bound),
                               np.full(2, np.pi)]).astype(np.float32)
        self.observation_space = spaces.Box(-high, high, dtype=np.float32)
        self._obs_high = high
        self._obs_low = -high

    def _set_action_scale(self, action: str) -> None:
        vehicle = _vehicle_file(self.scenario)
        thrusters = vehicle.thrusters
        if action == "thrusters":
            if thrusters is None:
                raise ValueError(f"argument 'action': 'thrusters' needs a thruster layout, and vehicle file "
                                 f"{self.scenario.vehicle_path()} has no [thrusters] table")
            self.matrix: Array | None = np.asarray(thrusters["matrix"], dtype=np.float64)
            self.pos = np.asarray(thrusters["max_thrust"], dtype=np.float64)
            self.neg = -np.asarray(thrusters["min_thrust"], dtype=np.float64)
        else:
            self.matrix = None
            if thrusters is not None:
                self.pos, self.neg = single_dof_limits(thrusters["matrix"], thrusters["min_thrust"],
                                                       thrusters["max_thrust"])
            else:
                tau_max = vehicle.tau_max
                if tau_max is None:
                    raise ValueError(f"vehicle file {self.scenario.vehicle_path()} has neither a [thrusters] "
                                     "table nor [limits] tau_max, so the action cannot be normalised")
                self.pos = self.neg = tau_max
        if np.any(self.neg <= 0) or np.any(self.pos <= 0):
            raise ValueError("thrusters: every thruster must be able to push both ways "
                             "(min_thrust < 0 < max_thrust) for a normalised action")
        self._symmetric = bool(np.array_equal(self.pos, self.neg))
        n = self.pos.shape[0]
        self.action_space = spaces.Box(-1.0, 1.0, shape=(n,), dtype=np.float32)
        self.action_shape = (n,)

    def clip(self, a: Array) -> tuple[Array, NDArray[np.bool_] | bool]:
        """The actions (K, n) clipped to [-1, 1] and which rows needed it
        (False: none). ValueError naming the rows with a non-finite entry."""
        # Written for speed (a single step's budget is ~20 us): the common case is two reductions.
        if np.abs(a).max() <= 1.0:  # NaN fails it
            return a, False
        finite = np.isfinite(a).all(axis=1)
        if not finite.all():
            rows = np.flatnonzero(~finite)
            raise ValueError(f"argument 'action' must be finite, got {a[rows[0]].tolist()} in row "
                             f"{int(rows[0])} (rows {rows.tolist()} are not)")
        return np.clip(a, -1.0, 1.0), ((a > 1.0) | (a < -1.0)).any(axis=1)

    def force(self, a: Array) -> Array:
        """The body forces tau (K, 6) the clipped actions (K, n) stand for."""
        u = a * self.pos if self._symmetric else a * np.where(a >= 0, self.pos, self.neg)
        return u if self.matrix is None else u @ self.matrix.T

    def observe(self, eta: Array, nu: Array, eta_d: Array, eta_d_dot: Array,
                eta_d_ddot: Array) -> NDArray[np.float32]:
        """The observations (K, 26) of the measured eta, nu and the desired
        state (K, 6 each), clipped to the space; a dropout's NaN reads 0."""
        eta, nu = self._readable(eta, nu)
        b = self._errors(eta, eta_d, eta_d_dot, eta_d_ddot)
        return self._observation(b, eta, nu)

    def observe_outcome(self, eta: Array, nu: Array, eta_d: Array, eta_d_dot: Array, eta_d_ddot: Array,
                        eta_true: Array, a: Array, diverged: NDArray[np.bool_] | bool,
                        done: NDArray[np.bool_] | bool, steps_left: NDArray[np.int64] | int
                        ) -> tuple[NDArray[np.float32], Array, NDArray[np.bool_], NDArray[np.bool_],
                                   NDArray[np.bool_]]:
        """observe() and outcome() of one instant in one pass (the same
        numbers; about half the numpy calls, which at K = 1 are the cost)."""
        eta, nu = self._readable(eta, nu)
        b = self._errors(eta, eta_d, eta_d_dot, eta_d_ddot, eta_true, a)
        return (self._observation(b, eta, nu), *self._score(b, eta_true, diverged, done, steps_left))

    def outcome(self, eta_true: Array, eta_d: Array, a: Array, diverged: NDArray[np.bool_] | bool,
                done: NDArray[np.bool_] | bool, steps_left: NDArray[np.int64] | int
                ) -> tuple[Array, NDArray[np.bool_], NDArray[np.bool_], NDArray[np.bool_]]:
        """(reward, terminated, truncated, outside the box), each (K,), of the
        rows after a step: eta_true and eta_d (K, 6), the clipped actions a
        (K, n), the plant's divergence and end and the steps not simulated
        ((K,) each, or one value for all rows)."""
        b = self._buffers(eta_true.shape[0])
        self._true_errors(b, eta_true, eta_d, a)
        wrap(b.true_angles, out=b.true_angles, scratch=b.turns[:, 3:])
        return self._score(b, eta_true, diverged, done, steps_left)

    def _readable(self, eta: Array, nu: Array) -> tuple[Array, Array]:
        """The measurements with a dropout's NaN (or Inf) read as 0."""
        if not self.check_faults:
            return eta, nu
        return (np.nan_to_num(eta, nan=0.0, posinf=0.0, neginf=0.0),
                np.nan_to_num(nu, nan=0.0, posinf=0.0, neginf=0.0))

    def _buffers(self, k: int) -> _Scratch:
        b = self._scratch.get(k)
        if b is None:
            b = self._scratch[k] = _Scratch(k, self.action_shape[0])
        return b

    def _errors(self, eta: Array, eta_d: Array, eta_d_dot: Array, eta_d_ddot: Array,
                eta_true: Array | None = None, a: Array | None = None) -> _Scratch:
        """The buffers filled: the measured pose error and the desired rates,
        and with eta_true the true pose error and the action; angles wrapped."""
        b = self._buffers(eta.shape[0])
        np.subtract(eta, eta_d, out=b.error)
        b.angles[...] = b.error_angles
        b.rate[...] = eta_d_dot
        b.accel[...] = eta_d_ddot
        if eta_true is None:
            wrap(b.angles, out=b.angles, scratch=b.turns[:, :3])
        else:
            self._true_errors(b, eta_true, eta_d, a)
            wrap(b.both_angles, out=b.both_angles, scratch=b.turns)
        return b

    @staticmethod
    def _true_errors(b: _Scratch, eta_true: Array, eta_d: Array, a: Array) -> None:
        np.subtract(eta_true[:, 3:], eta_d[:, 3:], out=b.true_angles)
        np.subtract(eta_true[:, :3], eta_d[:, :3], out=b.true_position)
        b.action[...] = a

    def _observation(self, b: _Scratch, eta: Array, nu: Array) -> NDArray[np.float32]:
        body = _core.to_body(eta, b.earth)
        obs = np.concatenate((body[:, 0, :3], b.angles, nu, body[:, 1], body[:, 2], eta[:, 3:5]),
                             axis=1, dtype=np.float32)
        np.minimum(obs, self._obs_high, out=obs)
        return np.maximum(obs, self._obs_low, out=obs)

    def _score(self, b: _Scratch, eta_true: Array, diverged: NDArray[np.bool_] | bool,
               done: NDArray[np.bool_] | bool, steps_left: NDArray[np.int64] | int
               ) -> tuple[Array, NDArray[np.bool_], NDArray[np.bool_], NDArray[np.bool_]]:
        # The wrapped true pose error and the action side by side: one weighted sum of squares.
        reward = np.square(b.scored, out=b.scored) @ self._neg_square_weights
        offset = np.abs(np.subtract(eta_true[:, :3], self._box_centre, out=b.offset), out=b.offset)
        # Any coordinate not inside (a boolean matmul is an any(), cheaper than .any(axis=1)); NaN is outside.
        outside = np.invert(offset <= self._box_half) @ self._ones
        terminated = outside | diverged
        if np.logical_or.reduce(terminated):
            # Ending early must not pay: each step left costs what the box's diagonal would.
            reward = np.where(terminated, reward - self.termination_cost * steps_left, reward)
        return reward, terminated, np.greater(done, terminated), outside  # done > terminated: done and not it

    def describe_end(self, t: float, diverged: bool, outside: bool) -> str:
        """Why an episode ended, for the error of a step after it."""
        why = ("the plant diverged" if diverged else
               "the vehicle left the bounding box" if outside else "the scenario's duration is simulated")
        return f"the episode ended at t = {t:g} s ({why}); call reset()"
