"""neurov.gym.sb3.TrackingSB3VecEnv: Stable-Baselines3's VecEnv contract on
the vector env. Skipped where SB3 (and PyTorch) are not installed, as in CI
(docs/gymnasium.md)."""

from __future__ import annotations

import numpy as np
import pytest

pytest.importorskip("stable_baselines3")
from neurov.gym import TrackingVectorEnv, resolve_scenario  # noqa: E402
from neurov.gym.sb3 import TrackingSB3VecEnv  # noqa: E402
from stable_baselines3 import PPO  # noqa: E402
from stable_baselines3.common.vec_env import VecEnv, VecMonitor  # noqa: E402

SHORT = resolve_scenario("paper_fig3").replace(duration=1.2)


def test_episode_ends_give_the_terminal_observation_and_reset_in_the_same_step() -> None:
    env = TrackingSB3VecEnv(3, scenario=SHORT)
    assert isinstance(env, VecEnv) and env.num_envs == 3
    env.seed(4)
    obs = env.reset()
    assert obs.shape == (3, 26) and obs.dtype == np.float32
    reference = TrackingVectorEnv(3, SHORT)
    want, _ = reference.reset(seed=4)
    np.testing.assert_array_equal(obs, want)
    for step in range(7):
        env.step_async(np.zeros((3, 6), dtype=np.float32))
        obs, rewards, dones, infos = env.step_wait()
        last, *_ = reference.step(np.zeros((3, 6)))
        assert rewards.dtype == np.float32 and dones.shape == (3,) and len(infos) == 3
    assert dones.all()
    for i, info in enumerate(infos):
        np.testing.assert_array_equal(info["terminal_observation"], last[i])
        assert info["TimeLimit.truncated"]
    np.testing.assert_array_equal(env.get_attr("num_envs", [0, 1]), [3, 3])
    env.close()


def test_ppo_learns_on_it() -> None:
    env = VecMonitor(TrackingSB3VecEnv(4, scenario=SHORT))
    model = PPO("MlpPolicy", env, n_steps=16, batch_size=32, n_epochs=1, seed=0, device="cpu")
    model.learn(total_timesteps=128)
    action, _ = model.predict(env.reset(), deterministic=True)
    assert action.shape == (4, 6)


def test_only_same_step_autoreset_is_taken() -> None:
    with pytest.raises(ValueError, match="SameStep"):
        TrackingSB3VecEnv(env=TrackingVectorEnv(2, SHORT))
