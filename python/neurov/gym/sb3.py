"""The vector environment as a Stable-Baselines3 ``VecEnv``: SB3 steps the K
envs of one :class:`neurov.gym.TrackingVectorEnv` (SAME_STEP autoreset, as
SB3 expects) in one call, with no Python env per lane. Needs
Stable-Baselines3 (and PyTorch): ``pip install stable-baselines3``.

    from neurov.gym.sb3 import TrackingSB3VecEnv
    model = PPO("MlpPolicy", TrackingSB3VecEnv(64, scenario="paper_fig3"))
"""

from __future__ import annotations

from collections.abc import Iterable, Sequence
from typing import Any

import numpy as np
from gymnasium.vector import AutoresetMode

try:
    from stable_baselines3.common.vec_env import VecEnv
except ImportError as e:  # pragma: no cover - SB3 is optional (not in CI)
    raise ImportError("neurov.gym.sb3 needs Stable-Baselines3 and PyTorch: pip install stable-baselines3") from e

from neurov.gym.vector import TrackingVectorEnv

__all__ = ["TrackingSB3VecEnv"]


class TrackingSB3VecEnv(VecEnv):
    """`num_envs` tracking envs for SB3 (the other arguments are those of
    :class:`TrackingVectorEnv`), or `env`, a TrackingVectorEnv in SAME_STEP
    mode. A lane's episode end gives its info ``terminal_observation`` and
    ``TimeLimit.truncated``, as SB3's own vector envs do; ``seed(s)`` seeds
    env i with s + i at the next reset."""

    def __init__(self, num_envs: int | None = None, *, env: TrackingVectorEnv | None = None,
                 **kwargs: Any) -> None:
        if env is None:
            if num_envs is None:
                raise ValueError("argument 'num_envs' is needed when no 'env' is given")
            env = TrackingVectorEnv(num_envs, autoreset_mode=AutoresetMode.SAME_STEP, **kwargs)
        elif num_envs is not None or kwargs:
            raise ValueError("give either 'env' or num_envs and the env's arguments, not both")
        if not isinstance(env, TrackingVectorEnv) or env.autoreset_mode != AutoresetMode.SAME_STEP:
            raise ValueError("argument 'env' must be a TrackingVectorEnv with autoreset_mode=SameStep "
                             "(SB3 resets an env in the step that ends its episode)")
        self.env = env
        super().__init__(env.num_envs, env.single_observation_space, env.single_action_space)
        self._actions: np.ndarray | None = None

    def reset(self) -> np.ndarray:
        seeds = self._seeds if any(s is not None for s in self._seeds) else None
        obs, _ = self.env.reset(seed=seeds)
        self._reset_seeds()
        self._reset_options()
        return obs

    def step_async(self, actions: np.ndarray) -> None:
        self._actions = actions

    def step_wait(self) -> tuple[np.ndarray, np.ndarray, np.ndarray, list[dict[str, Any]]]:
        obs, reward, terminated, truncated, info = self.env.step(self._actions)
        dones = terminated | truncated
        infos: list[dict[str, Any]] = [{} for _ in range(self.num_envs)]
        for i in np.flatnonzero(dones).tolist():
            infos[i] = {"terminal_observation": info["final_obs"][i],
                        "TimeLimit.truncated": bool(truncated[i] and not terminated[i])}
        return obs, reward.astype(np.float32), dones, infos

    def close(self) -> None:
        self.env.close()

    def _count(self, indices: Any) -> int:
        return len(list(self._get_indices(indices)))

    def get_attr(self, attr_name: str, indices: Any = None) -> list[Any]:
        """The attribute of the vector env, once per index (the lanes share it)."""
        return [getattr(self.env, attr_name)] * self._count(indices)

    def set_attr(self, attr_name: str, value: Any, indices: Any = None) -> None:
        raise AttributeError(f"TrackingSB3VecEnv.set_attr({attr_name!r}): the lanes share one vector env, "
                             "whose attributes are not set per lane")

    def env_method(self, method_name: str, *method_args: Any, indices: Any = None, **method_kwargs: Any) -> list[Any]:
        """The vector env's method, called once (the lanes share it)."""
        return [getattr(self.env, method_name)(*method_args, **method_kwargs)] * self._count(indices)

    def env_is_wrapped(self, wrapper_class: type, indices: Iterable[int] | Sequence[int] | int | None = None
                       ) -> list[bool]:
        return [False] * self._count(indices)
