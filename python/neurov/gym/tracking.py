"""The tracking task as a Gymnasium environment: a scenario's vehicle,
thrusters, current, disturbances, noise and faults (everything of a run but
the controller), with the agent as the controller.

The observation, the action, the reward and the episode's end are documented
in docs/gymnasium.md; the class docstring is the short form."""

from __future__ import annotations

import math
import operator
from pathlib import Path
from typing import Any

import gymnasium
import numpy as np
from gymnasium import spaces
from numpy.typing import NDArray

from neurov import _core
from neurov.laws.protocol import as_real_numbers
from neurov.gym.limits import single_dof_limits
from neurov.config.vehicle_file import VehicleFile, read_vehicle_file
from neurov.config.reading import load_scenario
from neurov.config.scenario import Scenario, ScenarioError, scenario_path
from neurov.running.plant import build_vehicle, simulation_config

__all__ = ["TrackingEnv", "resolve_scenario"]

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


def _wrap(angle: float) -> float:
    """The angle in [-pi, pi]."""
    return math.remainder(angle, math.tau)


class TrackingEnv(gymnasium.Env):
    """Track a scenario's reference with the body force tau (action="body",
    six numbers in [-1, 1] scaled by what each DOF can get alone) or with the
    thruster commands (action="thrusters", one number in [-1, 1] per
    thruster, scaled by its limits).

    Observation (float32, 26): the pose error eta - eta_d with its position
    part in the body frame and its angles wrapped to [-pi, pi] (6); the
    measured nu (6); the desired velocity J(eta)^-1 eta_d_dot (6) and
    acceleration J(eta)^-1 eta_d_ddot (6) in the body frame; the measured roll
    and pitch (2). Each is clipped to the space's bounds; a sensor dropout's
    NaN reads 0.

    Reward: minus the sum of position_weight times the squared distance
    from the true position p to p_d, attitude_weight times the squared
    norm of the wrapped attitude error, and effort_weight times the squared
    norm of the (clipped) action.
    terminated: the plant diverged, or the true position left the commanded
    path's bounding box grown by `box_margin` metres; the last reward then
    also pays position_weight d^2 for each step not simulated (d the box's
    diagonal), so ending early never pays. truncated: the scenario's
    duration is simulated.

    Actions outside the space are clipped; `info["action_clips"]` counts the
    steps of the episode that needed it. A non-finite action, a wrong shape,
    or a step before reset or after the episode ended raise and change
    nothing."""

    metadata: dict[str, Any] = {"render_modes": ["rgb_array"], "render_fps": 5}

    def __init__(self, scenario: Scenario | str | Path = "paper_fig3", action: str = "body",
                 render_mode: str | None = None, *, position_weight: float = 1.0,
                 attitude_weight: float = 1.0, effort_weight: float = 0.01, box_margin: float = 5.0,
                 velocity_bound: float = 5.0) -> None:
        if action not in ("body", "thrusters"):
            raise ValueError(f"argument 'action' must be 'body' or 'thrusters', got {action!r}")
        if render_mode is not None and render_mode not in self.metadata["render_modes"]:
            raise ValueError(f"argument 'render_mode' must be None or 'rgb_array', got {render_mode!r}")
        for name, v in (("position_weight", position_weight), ("attitude_weight", attitude_weight),
                        ("effort_weight", effort_weight)):
            if not (np.isfinite(v) and v >= 0):
                raise ValueError(f"argument {name!r} must be a finite number >= 0, got {v!r}")
        for name, v in (("box_margin", box_margin), ("velocity_bound", velocity_bound)):
            if not (np.isfinite(v) and v > 0):
                raise ValueError(f"argument {name!r} must be a finite number > 0, got {v!r}")
        self.scenario = resolve_scenario(scenario)
        self.action_kind = action
        self.render_mode = render_mode
        self.metadata = {**self.metadata, "render_fps": max(1, round(1.0 / self.scenario.dt))}
        self._weights = (float(position_weight), float(attitude_weight), float(effort_weight))

        self._config = simulation_config(self.scenario)
        self._sim = _core.Simulator(build_vehicle(self.scenario), self._config)
        self._check_faults = len(self._config.sensor_faults) > 0
        self._set_action_scale(action)

        poses = np.asarray(self._config.command.poses)
        corners = np.vstack([poses[:, :3], np.asarray(self._config.eta0)[:3]])
        self.box_low = corners.min(axis=0) - box_margin
        self.box_high = corners.max(axis=0) + box_margin
        reach = float(np.linalg.norm(self.box_high - self.box_low))
        self._termination_cost = float(position_weight) * reach**2
        high = np.concatenate([np.full(3, reach), np.full(3, np.pi), np.full(18, velocity_bound),
                               np.full(2, np.pi)]).astype(np.float32)
        self.observation_space = spaces.Box(-high, high, dtype=np.float32)
        self._obs_high = high
        self._obs_low = -high
        self._box = (tuple(self.box_low.tolist()), tuple(self.box_high.tolist()))
        self._cols = np.zeros((3, 6))  # eta - eta_d, eta_d_dot, eta_d_ddot

        self._episode_over: str | None = "call reset() before step()"
        self._clips = 0
        self._track: list[tuple[float, float, float, float]] = []

    def _set_action_scale(self, action: str) -> None:
        vehicle = _vehicle_file(self.scenario)
        thrusters = vehicle.thrusters
        if action == "thrusters":
            if thrusters is None:
                raise ValueError(f"argument 'action': 'thrusters' needs a thruster layout, and vehicle file "
                                 f"{self.scenario.vehicle_path()} has no [thrusters] table")
            self._matrix = np.asarray(thrusters["matrix"], dtype=np.float64)
            self._pos = np.asarray(thrusters["max_thrust"], dtype=np.float64)
            self._neg = -np.asarray(thrusters["min_thrust"], dtype=np.float64)
        else:
            self._matrix = None
            if thrusters is not None:
                self._pos, self._neg = single_dof_limits(thrusters["matrix"], thrusters["min_thrust"],
                                                         thrusters["max_thrust"])
            else:
                tau_max = vehicle.tau_max
                if tau_max is None:
                    raise ValueError(f"vehicle file {self.scenario.vehicle_path()} has neither a [thrusters] "
                                     "table nor [limits] tau_max, so the action cannot be normalised")
                self._pos = self._neg = tau_max
        if np.any(self._neg <= 0) or np.any(self._pos <= 0):
            raise ValueError("thrusters: every thruster must be able to push both ways "
                             "(min_thrust < 0 < max_thrust) for a normalised action")
        self._symmetric = bool(np.array_equal(self._pos, self._neg))
        n = self._pos.shape[0]
        self.action_space = spaces.Box(-1.0, 1.0, shape=(n,), dtype=np.float32)
        self._action_shape = (n,)

    @property
    def action_scale(self) -> tuple[Array, Array]:
        """(positive, negative): what action +1 and -1 stand for per component
        (N or N m for action="body", N of thrust for action="thrusters")."""
        return self._pos.copy(), self._neg.copy()

    def _force(self, a: Array) -> Array:
        """The body force tau the action stands for."""
        u = a * self._pos if self._symmetric else a * np.where(a >= 0, self._pos, self._neg)
        return u if self._matrix is None else self._matrix @ u

    def reset(self, *, seed: int | None = None, options: dict[str, Any] | None = None
              ) -> tuple[NDArray[np.float32], dict[str, Any]]:
        """Back to t = 0. The measurement noise is seeded from `seed`; None
        draws a seed from the environment's generator (itself seeded by the
        last reset with a seed), so the same seed gives the same episode."""
        if seed is not None:
            # First: the core refuses a seed outside its range (saying it) before anything changes.
            self._sim.reset(seed)
        super().reset(seed=seed)
        if seed is None:
            self._sim.reset(int(self.np_random.integers(2**63 - 1)))
        self._episode_over = None
        self._clips = 0
        obs, info = self._observe()
        if self.render_mode is not None:
            self._track = [(*info["eta_true"][:2].tolist(), *info["eta_d"][:2].tolist())]
        return obs, info

    def _observe(self) -> tuple[NDArray[np.float32], dict[str, Any]]:
        # Written for speed (a step's budget is ~20 us): few numpy calls on
        # six-vectors, a preallocated buffer, scalars in plain Python.
        o = self._sim.observation
        eta_raw, nu_raw, eta_d = o.eta, o.nu, o.eta_d
        eta, nu = eta_raw, nu_raw
        if self._check_faults:
            eta = np.nan_to_num(eta, nan=0.0, posinf=0.0, neginf=0.0)
            nu = np.nan_to_num(nu, nan=0.0, posinf=0.0, neginf=0.0)
        cols = self._cols
        np.subtract(eta, eta_d, out=cols[0])
        cols[1] = o.eta_d_dot
        cols[2] = o.eta_d_ddot
        body = cols @ _core.jacobian_inverse(eta).T  # rows: J^-1 (eta - eta_d), J^-1 eta_d_dot, J^-1 eta_d_ddot
        e_phi, e_theta, e_psi = cols[0, 3:].tolist()
        obs = np.concatenate((body[0, :3], (_wrap(e_phi), _wrap(e_theta), _wrap(e_psi)), nu, body[1], body[2],
                              eta[3:5]), dtype=np.float32)
        np.minimum(obs, self._obs_high, out=obs)
        np.maximum(obs, self._obs_low, out=obs)
        eta_true, nu_true = self._sim.state
        info = {"t": o.t, "eta": eta_raw, "nu": nu_raw, "eta_d": eta_d, "eta_true": eta_true, "nu_true": nu_true,
                "action_clips": self._clips}
        return obs, info

    def step(self, action: Any) -> tuple[NDArray[np.float32], float, bool, bool, dict[str, Any]]:
        """Applies the action for one control period; returns (observation,
        reward, terminated, truncated, info). RuntimeError before reset() or
        after the episode ended; ValueError for a wrong shape or a non-finite
        action, TypeError for one that is not real numbers (a dict, str,
        bool or complex values; nothing is simulated then)."""
        if self._episode_over is not None:
            raise RuntimeError(f"TrackingEnv.step: {self._episode_over}")
        try:
            a = as_real_numbers(action)
        except Exception as exc:  # a dict, a str, bools, complex numbers: the reason names the type
            raise TypeError(f"TrackingEnv.step: argument 'action' must hold real numbers (shape "
                            f"{self._action_shape}), got {exc}") from None
        if a.shape != self._action_shape:
            raise ValueError(f"TrackingEnv.step: argument 'action' must have shape {self._action_shape}, "
                             f"got {a.shape}")
        values = a.tolist()
        # A non-finite entry makes the sum non-finite (so does an overflow, checked below).
        if not (math.isfinite(sum(values)) and max(values) <= 1.0 and min(values) >= -1.0):
            if not np.isfinite(a).all():
                raise ValueError(f"TrackingEnv.step: argument 'action' must be finite, got {values}")
            a = np.clip(a, -1.0, 1.0)
            values = a.tolist()
            self._clips += 1
        plant = self._sim.step(self._force(a))
        obs, info = self._observe()
        info["plant_status"] = plant
        x, y, z, phi, theta, psi = info["eta_true"].tolist()
        xd, yd, zd, phid, thetad, psid = info["eta_d"].tolist()
        wp, wa, wu = self._weights
        reward = -(wp * ((x - xd) ** 2 + (y - yd) ** 2 + (z - zd) ** 2)
                   + wa * (_wrap(phi - phid) ** 2 + _wrap(theta - thetad) ** 2 + _wrap(psi - psid) ** 2)
                   + wu * sum(map(operator.mul, values, values)))
        (xl, yl, zl), (xh, yh, zh) = self._box
        outside = not (xl <= x <= xh and yl <= y <= yh and zl <= z <= zh)
        diverged = self._sim.diverged
        terminated = diverged or outside
        truncated = not terminated and self._sim.done
        if terminated:
            # Ending early must not pay: each step left costs what the box's diagonal would.
            reward -= self._termination_cost * (self._sim.planned_steps - self._sim.steps)
        if terminated or truncated:
            why = ("the plant diverged" if diverged else
                   "the vehicle left the bounding box" if outside else "the scenario's duration is simulated")
            self._episode_over = f"the episode ended at t = {info['t']:g} s ({why}); call reset()"
        if self.render_mode is not None:
            self._track.append((x, y, xd, yd))
        return obs, reward, terminated, truncated, info

    def render(self) -> NDArray[np.uint8] | None:
        """The top view (north up, east right) as an RGB array: the commanded
        poses, the desired and the true path so far, the vehicle's heading,
        its depth against the desired one within the box, and the time.
        Before the first reset(), gymnasium's ResetNeeded."""
        if self.render_mode is None:
            return None
        if not self._track:
            raise gymnasium.error.ResetNeeded("TrackingEnv.render: call reset() before render()")
        # Deferred: rendering draws with Matplotlib.
        from neurov.gym.render import top_view

        eta = self._sim.state[0]
        o = self._sim.observation
        return top_view(np.asarray(self._config.command.poses), np.asarray(self._track), float(eta[5]),
                        self.box_low, self.box_high, t=float(o.t), depth=float(eta[2]),
                        depth_desired=float(o.eta_d[2]))
