"""K tracking environments as one ``gymnasium.vector.VectorEnv``: one batch
of runs (``neurov._core.BatchSimulator``) stepped, observed and scored for
all K in one call into C++ per step by the single environment's own task
(:class:`neurov.gym.task.TrackingTask`); Python does the autoresets.

    envs = gymnasium.make_vec("neurov/Tracking-v0", num_envs=256,
                              vectorization_mode="vector_entry_point", scenario="paper_fig3")

docs/gymnasium.md gives the autoreset modes, the seeding and the
randomisation."""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path
from typing import Any

import numpy as np
from gymnasium.utils import seeding
from gymnasium.vector import AutoresetMode, VectorEnv
from gymnasium.vector.utils import batch_space
from numpy.typing import NDArray

from neurov import _core
from neurov.gym.randomize import Randomization
from neurov.gym.task import TrackingTask, resolve_scenario
from neurov.gym.tracking import TrackingEnv
from neurov.config.scenario import Scenario
from neurov.memory import heap_bytes, require_memory
from neurov.running.plant import build_vehicle, simulation_config

__all__ = ["TrackingVectorEnv"]

_MODES = (AutoresetMode.NEXT_STEP, AutoresetMode.SAME_STEP)


#: Envs of the batch built to measure an env's memory (a larger one is checked against the memory there is).
_PROBE_ENVS = 64
#: Bytes an env's arrays take in Python (the batched spaces' bounds, a step's observation, info,
#: rewards and flags, the lists the batch is built from), rounded up.
_PYTHON_ENV_BYTES = 2048


def _check_memory(k: int, vehicle: _core.Vehicle, config: _core.SimulationConfig) -> None:
    """Refuses `k` envs whose memory would not fit (neurov.memory), before
    the batch is built: an env's bytes measured on a batch of
    _PROBE_ENVS, twice over (the batch copies each env's vehicle and
    configuration once more while it is built)."""
    if k <= _PROBE_ENVS:
        return
    before = heap_bytes()
    probe = _core.BatchSimulator([vehicle] * _PROBE_ENVS, [config] * _PROBE_ENVS, log_rows=1)
    after = heap_bytes()
    del probe
    if before is None or after is None:
        return
    per_env = 2 * max(after - before, 0) // _PROBE_ENVS + _PYTHON_ENV_BYTES
    require_memory(k * per_env, f"argument 'num_envs' = {k} ({per_env / 1024:.1f} kB an env)", ValueError)


class TrackingVectorEnv(VectorEnv):
    """`num_envs` copies of :class:`neurov.gym.TrackingEnv` (the same
    arguments, the same observation, action, reward and episode end) stepped
    as one batch.

    autoreset_mode: ``AutoresetMode.NEXT_STEP`` (gymnasium's default: the
    step after an episode ended resets that env, ignoring its action, and
    returns its first observation with reward 0) or
    ``AutoresetMode.SAME_STEP`` (the step that ends an episode resets the env
    at once and returns its first observation, the last one in
    ``info["final_obs"]`` and its info in ``info["final_info"]``: what
    Stable-Baselines3 expects). A string ("NextStep", "SameStep") is taken
    too. (``AutoresetMode.DISABLED`` is not offered.)

    ``reset(options={"reset_mask": mask})`` (gymnasium's partial reset, in
    either mode) resets only the envs where `mask` (a bool array of
    `num_envs`) is True, clearing their pending autoreset; the others go on
    as they were and their observations are returned as they stand. It is
    the one option: any other key, or options that are not a dict, are
    refused.

    Seeding: ``reset(seed=s)`` seeds env i with s + i (a list gives each
    env's seed), so env i is the single env under ``reset(seed=s + i)``; its
    later episodes draw their noise seeds (and, with `randomize`, their
    plants) from env i's own generator, as the single env does.

    randomize: a perturbation table in the study file's form (a list of
    tables as ``[[perturbations]]``): each env draws its plant from it at
    every reset. `batch_class`: the batch to run (default the compiled
    ``neurov._core.BatchSimulator``; :class:`neurov.running.lanes.PythonLanes`
    steps one simulator per env, the reference it is tested against).
    threads: the threads that step the compiled batch's plants (0, the
    default: one per core; at least ``neurov._core.MIN_LANES_PER_THREAD``
    (128) envs a thread, so a smaller batch steps on one); the results do
    not depend on it.

    Memory: an env holds its run's state, not its rows (the compiled batch
    keeps a log window of one row). A `num_envs` whose memory would not fit
    in what the machine has available, or under the process's address-space
    limit (``ulimit -v``), is refused before anything is built: a
    ValueError naming the memory it would need (:mod:`neurov.memory`)."""

    metadata: dict[str, Any] = {"render_modes": [], "autoreset_mode": AutoresetMode.NEXT_STEP}

    def __init__(self, num_envs: int, scenario: Scenario | str | Path = "paper_fig3", action: str = "body", *,
                 autoreset_mode: AutoresetMode | str = AutoresetMode.NEXT_STEP, randomize: Any = None,
                 position_weight: float = 1.0, attitude_weight: float = 1.0, effort_weight: float = 0.01,
                 box_margin: float = 5.0, velocity_bound: float = 5.0, batch_class: type | None = None,
                 threads: int = 0, render_mode: None = None) -> None:
        if isinstance(num_envs, bool) or not isinstance(num_envs, (int, np.integer)) or num_envs < 1:
            raise ValueError(f"argument 'num_envs' must be an int >= 1, got {num_envs!r}")
        if isinstance(threads, bool) or not isinstance(threads, (int, np.integer)) or not 0 <= threads < 2**32:
            raise ValueError(f"argument 'threads' must be an int >= 0 (0: one per core), got {threads!r}")
        self.threads = int(threads)
        if render_mode is not None:
            raise ValueError(f"argument 'render_mode': the vector env does not render, got {render_mode!r}")
        try:
            mode = AutoresetMode(autoreset_mode)
        except ValueError:
            mode = None
        if mode not in _MODES:
            raise ValueError(f"argument 'autoreset_mode' must be one of {[m.value for m in _MODES]}, "
                             f"got {autoreset_mode!r}")
        self.num_envs = int(num_envs)
        self.scenario = resolve_scenario(scenario)
        config = simulation_config(self.scenario)
        self.task = TrackingTask(self.scenario, config, action, position_weight=position_weight,
                                 attitude_weight=attitude_weight, effort_weight=effort_weight,
                                 box_margin=box_margin, velocity_bound=velocity_bound)
        self.randomization = Randomization.of(randomize, self.scenario)
        vehicle = build_vehicle(self.scenario)
        if batch_class is None:
            _check_memory(self.num_envs, vehicle, config)  # before the batched spaces, the first K-sized arrays
        self.autoreset_mode = mode
        self.metadata = {**self.metadata, "autoreset_mode": mode}
        self.render_mode = None
        self.single_observation_space = self.task.observation_space
        self.single_action_space = self.task.action_space
        self.observation_space = batch_space(self.single_observation_space, self.num_envs)
        self.action_space = batch_space(self.single_action_space, self.num_envs)

        k = self.num_envs
        if batch_class is None:
            # A window of one row: the env reads its observations, never a run's rows (859 kB an env
            # for paper_fig3's 1,251 rows, 3.4 GB at 4,096 envs, written as they stepped).
            self._batch = _core.BatchSimulator([vehicle] * k, [config] * k, log_rows=1)
        else:
            self._batch = batch_class([vehicle] * k, [config] * k)
        self._compiled = isinstance(self._batch, _core.BatchSimulator)
        self._rngs: list[np.random.Generator | None] = [None] * k
        self._clips = np.zeros(k, dtype=np.int64)
        self._ended = np.zeros(k, dtype=bool)  # NEXT_STEP: reset at the next step
        self._every = np.ones(k, dtype=bool)
        self._every.flags.writeable = False
        self._started = False

    # --- resets -----------------------------------------------------------------------------------

    def _lane_seeds(self, seed: int | Sequence[int | None] | None) -> list[int | None]:
        k = self.num_envs
        if seed is None:
            seeds: list[Any] = [None] * k
        elif isinstance(seed, (int, np.integer)) and not isinstance(seed, bool):
            seeds = [int(seed) + i for i in range(k)]
        elif isinstance(seed, Sequence) and not isinstance(seed, str) and len(seed) == k:
            seeds = list(seed)
        else:
            raise ValueError(f"argument 'seed' must be None, an int or a list of {k} ints or None, got {seed!r}")
        for i, s in enumerate(seeds):
            if s is not None and (isinstance(s, bool) or not isinstance(s, (int, np.integer))
                                  or not 0 <= s < 2**64):
                raise ValueError(f"argument 'seed': env {i}'s seed must be an int in [0, 2**64), got {s!r}")
        return seeds

    def _reset_lanes(self, lanes: NDArray[np.intp], seeds: Sequence[int | None]) -> None:
        """Env i of `lanes` at t = 0: its generator re-seeded by seeds[i] if
        given, its plant drawn (randomize), then its noise seed."""
        noise = np.zeros(self.num_envs, dtype=np.uint64)
        mask = np.zeros(self.num_envs, dtype=bool)
        for i in lanes.tolist():
            s = seeds[i]
            if s is not None or self._rngs[i] is None:
                self._rngs[i] = seeding.np_random(s)[0]
            rng = self._rngs[i]
            assert rng is not None
            if self.randomization is not None:
                self._batch.replace(i, *self.randomization.draw(rng))
            noise[i] = TrackingEnv.episode_seed(rng, s)
            mask[i] = True
        self._batch.reset(noise, mask)
        self._clips[mask] = 0

    def _reset_mask(self, options: Any) -> NDArray[np.bool_] | None:
        """The envs `options` asks to reset (None: every env), checked as
        gymnasium checks them."""
        if options is None:
            return None
        if not isinstance(options, dict):
            raise TypeError(f"argument 'options' must be None or a dict (its one key 'reset_mask'), "
                            f"got {type(options).__name__}")
        unknown = sorted(map(repr, set(options) - {"reset_mask"}))
        if unknown:
            raise ValueError(f"argument 'options': unknown key(s) {', '.join(unknown)}; the one option is "
                             "'reset_mask' (a bool array of num_envs: the envs to reset)")
        if "reset_mask" not in options:
            return None
        mask = options["reset_mask"]
        k = self.num_envs
        if not isinstance(mask, np.ndarray) or mask.dtype != np.bool_ or mask.shape != (k,):
            got = f"an array of {mask.dtype} {mask.shape}" if isinstance(mask, np.ndarray) else type(mask).__name__
            raise TypeError(f"argument 'options': 'reset_mask' must be a numpy bool array of shape ({k},), got {got}")
        if not mask.any():
            raise ValueError("argument 'options': 'reset_mask' must have at least one True (the envs to reset)")
        if not self._started and not mask.all():
            raise RuntimeError("TrackingVectorEnv.reset: a partial reset (reset_mask) before the first reset; "
                               "call reset() for every env first")
        return mask.copy()

    def reset(self, *, seed: int | Sequence[int | None] | None = None, options: dict[str, Any] | None = None
              ) -> tuple[NDArray[np.float32], dict[str, Any]]:
        """Every env back to t = 0, or those of ``options["reset_mask"]``
        (see the class for the seeds and the options)."""
        self._require_open()
        seeds = self._lane_seeds(seed)
        mask = self._reset_mask(options)
        if mask is None:
            super().reset(seed=seed if isinstance(seed, (int, np.integer)) else None)
            mask = np.ones(self.num_envs, dtype=bool)
        self._reset_lanes(np.flatnonzero(mask), seeds)
        self._ended[mask] = False
        self._started = True
        obs, info = self._lanes()
        info["action_clips"] = self._clips.copy()
        info.update({f"_{key}": mask for key in list(info)})
        return obs, info

    # --- steps ------------------------------------------------------------------------------------

    def _lanes(self) -> tuple[NDArray[np.float32], dict[str, Any]]:
        """Every env's observation and info arrays (t, eta, nu, eta_d,
        eta_true, nu_true) as it stands."""
        if self._compiled:
            return self.task.core.observe_batch(self._batch)
        b = self._batch
        o = b.observation
        eta_true, nu_true = b.state
        obs = self.task.core.observe_rows(o["eta"], o["nu"], o["eta_d"], o["eta_d_dot"], o["eta_d_ddot"])
        return obs, {"t": o["t"], "eta": o["eta"], "nu": o["nu"], "eta_d": o["eta_d"], "eta_true": eta_true,
                     "nu_true": nu_true}

    def _observe(self) -> tuple[NDArray[np.float32], dict[str, Any]]:
        obs, info = self._lanes()
        info["action_clips"] = self._clips.copy()
        return obs, self._masked(info)

    def _masked(self, info: dict[str, Any]) -> dict[str, Any]:
        """info with gymnasium's mask _key beside each key: every env has it
        (one read-only array of K True, made once)."""
        every = self._every
        info.update({f"_{key}": every for key in list(info)})
        return info

    def _advance(self, actions: Any, stepped: NDArray[np.bool_] | None) -> tuple[Any, ...]:
        """The envs in `stepped` (None: every env) stepped under their
        actions: (obs, reward, terminated, truncated, info, clipped) of every
        env (reward 0 and no flag for one not stepped). The compiled batch
        does it all in one call into C++; another batch (PythonLanes)
        through the task's row functions."""
        core = self.task.core
        if self._compiled:
            return core.step_batch(self._batch, actions, stepped, self.threads)[:6]
        if stepped is None:
            stepped = self._every
        shape = (self.num_envs, *self.task.action_shape)
        a, clipped = core.clip(actions)  # refuses what is not real numbers, or not finite
        if a.shape != shape:
            raise ValueError(f"argument 'actions' must have shape {shape}, got {a.shape}")
        b = self._batch
        statuses = b.step(core.forces(a), stepped)
        obs, info = self._lanes()
        reward, terminated, truncated, _ = core.score_rows(info["eta_true"], info["eta_d"], a, b.diverged, b.done,
                                                           b.planned_steps - b.steps)
        idle = statuses == _core.LANE_NOT_STEPPED
        reward[idle], terminated[idle], truncated[idle] = 0.0, False, False
        info["plant_status"] = statuses
        return obs, reward, terminated, truncated, info, clipped

    def step(self, actions: Any) -> tuple[NDArray[np.float32], NDArray[np.float64], NDArray[np.bool_],
                                          NDArray[np.bool_], dict[str, Any]]:
        """Applies each env's action for one control period, all K and their
        observations, rewards and flags in one call into C++; (observations,
        rewards, terminated, truncated, info), each with K rows.
        ValueError/TypeError for actions of the wrong shape or type or with
        NaN/Inf (nothing is stepped then)."""
        self._require_open()
        if not self._started:
            raise RuntimeError("TrackingVectorEnv.step: call reset() before step()")
        # NEXT_STEP: the envs whose episode ended are not stepped (their action is ignored).
        waiting = self._ended.any()
        stepped = ~self._ended if waiting else None
        try:
            obs, reward, terminated, truncated, info, clipped = self._advance(actions, stepped)
        except (TypeError, ValueError) as e:
            raise type(e)(f"TrackingVectorEnv.step: {e}") from None
        if waiting:
            # ... and start again.
            self._reset_lanes(np.flatnonzero(self._ended), [None] * self.num_envs)
            obs, fresh = self._lanes()
            info.update(fresh)
            clipped &= stepped
        self._clips += clipped
        info["action_clips"] = self._clips.copy()
        self._masked(info)
        info["_plant_status"] = self._every if stepped is None else stepped
        ended = terminated | truncated
        if self.autoreset_mode == AutoresetMode.NEXT_STEP:
            self._ended = ended
        elif ended.any():
            obs, info = self._reset_in_step(ended, obs, info)
        return obs, reward, terminated, truncated, info

    def _reset_in_step(self, ended: NDArray[np.bool_], obs: NDArray[np.float32], info: dict[str, Any]
                       ) -> tuple[NDArray[np.float32], dict[str, Any]]:
        """SAME_STEP: the ended envs' last observation and info go to
        ``final_obs`` and ``final_info``, and they start again at once."""
        final_obs = np.full(self.num_envs, None, dtype=object)
        for i in np.flatnonzero(ended).tolist():
            final_obs[i] = obs[i].copy()
        final_info = {key: value for key, value in info.items() if not key.startswith("_")}
        final_info.update({f"_{key}": ended for key in list(final_info)})
        self._reset_lanes(np.flatnonzero(ended), [None] * self.num_envs)
        obs, new_info = self._observe()
        new_info.update(plant_status=info["plant_status"], _plant_status=~ended,
                        final_obs=final_obs, _final_obs=ended, final_info=final_info, _final_info=ended)
        return obs, new_info

    def _require_open(self) -> None:
        if self.closed:
            raise RuntimeError("TrackingVectorEnv: the environment is closed")

    def close_extras(self, **kwargs: Any) -> None:
        self._batch = None
