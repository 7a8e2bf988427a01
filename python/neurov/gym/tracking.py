"""The tracking task as a Gymnasium environment: a scenario's vehicle,
thrusters, current, disturbances, noise and faults (everything of a run but
the controller), with the agent as the controller.

The observation, the action, the reward and the episode's end are documented
in docs/gymnasium.md; the class docstring is the short form."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import gymnasium
import numpy as np
from numpy.typing import NDArray

from neurov import _core
from neurov.gym.randomize import Randomization
from neurov.gym.task import TrackingTask, resolve_scenario
from neurov.config.scenario import Scenario
from neurov.running.plant import build_vehicle, simulation_config

__all__ = ["TrackingEnv", "resolve_scenario"]

Array = NDArray[np.float64]


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
                 velocity_bound: float = 5.0, randomize: Any = None) -> None:
        if render_mode is not None and render_mode not in self.metadata["render_modes"]:
            raise ValueError(f"argument 'render_mode' must be None or 'rgb_array', got {render_mode!r}")
        self.scenario = resolve_scenario(scenario)
        self._config = simulation_config(self.scenario)
        self.task = TrackingTask(self.scenario, self._config, action, position_weight=position_weight,
                                 attitude_weight=attitude_weight, effort_weight=effort_weight,
                                 box_margin=box_margin, velocity_bound=velocity_bound)
        self.randomization = Randomization.of(randomize, self.scenario)
        self.action_kind = action
        self.render_mode = render_mode
        self.metadata = {**self.metadata, "render_fps": max(1, round(1.0 / self.scenario.dt))}
        self._sim = _core.Simulator(build_vehicle(self.scenario), self._config)
        self.observation_space = self.task.observation_space
        self.action_space = self.task.action_space
        self.box_low, self.box_high = self.task.box_low, self.task.box_high

        self._episode_over: str | None = "call reset() before step()"
        self._clips = 0
        self._track: list[tuple[float, float, float, float]] = []

    @property
    def action_scale(self) -> tuple[Array, Array]:
        """(positive, negative): what action +1 and -1 stand for per component
        (N or N m for action="body", N of thrust for action="thrusters")."""
        return self.task.pos.copy(), self.task.neg.copy()

    def reset(self, *, seed: int | None = None, options: dict[str, Any] | None = None
              ) -> tuple[NDArray[np.float32], dict[str, Any]]:
        """Back to t = 0. The measurement noise is seeded from `seed`; None
        draws a seed from the environment's generator (itself seeded by the
        last reset with a seed), so the same seed gives the same episode.
        With `randomize`, the episode's plant is drawn from that generator
        first (docs/gymnasium.md). It takes no options: `options` is None or
        an empty dict."""
        if options is not None and (not isinstance(options, dict) or options):
            raise ValueError(f"argument 'options': TrackingEnv.reset takes no options (None or {{}}), "
                             f"got {options!r}"[:300])
        if seed is not None:
            # First: the core refuses a seed outside its range (saying it) before anything changes.
            self._sim.reset(seed)
        super().reset(seed=seed)
        if self.randomization is not None:
            vehicle, config = self.randomization.draw(self.np_random)
            self._sim = _core.Simulator(vehicle, config)
        self._sim.reset(self.episode_seed(self.np_random, seed))
        self._episode_over = None
        self._clips = 0
        obs, info = self._observe()
        if self.render_mode is not None:
            self._track = [(*info["eta_true"][:2].tolist(), *info["eta_d"][:2].tolist())]
        return obs, info

    @staticmethod
    def episode_seed(rng: np.random.Generator, seed: int | None) -> int:
        """The noise seed of an episode: `seed` as given, else drawn from the
        environment's generator."""
        return int(rng.integers(2**63 - 1)) if seed is None else seed

    def _observe(self) -> tuple[NDArray[np.float32], dict[str, Any]]:
        obs, info = self.task.core.observe(self._sim)
        info["action_clips"] = self._clips
        return obs, info

    def step(self, action: Any) -> tuple[NDArray[np.float32], float, bool, bool, dict[str, Any]]:
        """Applies the action for one control period; returns (observation,
        reward, terminated, truncated, info). RuntimeError before reset() or
        after the episode ended; ValueError for a wrong shape or a non-finite
        action, TypeError for one that is not real numbers (a dict, str,
        bool or complex values; nothing is simulated then)."""
        if self._episode_over is not None:
            raise RuntimeError(f"TrackingEnv.step: {self._episode_over}")
        # One call into C++: the action checked, clipped and scaled, the step, the observation and the score.
        try:
            obs, reward, terminated, truncated, info, clipped, outside = self.task.core.step(self._sim, action)
        except (TypeError, ValueError) as e:
            raise type(e)(f"TrackingEnv.step: {e}") from None
        self._clips += clipped
        info["action_clips"] = self._clips
        if terminated or truncated:
            self._episode_over = self.task.describe_end(info["t"], self._sim.diverged, outside)
        if self.render_mode is not None:
            self._track.append((*info["eta_true"][:2].tolist(), *info["eta_d"][:2].tolist()))
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
