"""Train a PPO policy (Stable-Baselines3) on neurov/Tracking-v0 and compare it
with the scenario's own controller (the paper's NN controller for paper_fig3)
on the same scenario and seed. Optional: needs `pip install stable-baselines3`
(and PyTorch); not run in CI.

    python examples/train_ppo.py [--scenario paper_fig3] [--timesteps 50000] [--seed 0] [--envs K]

With --envs K, PPO trains on K envs of one neurov.gym.TrackingVectorEnv
(neurov.gym.sb3.TrackingSB3VecEnv: one batch, no Python env per lane); the
evaluation is the single env either way.

Prints the training time, then for the trained policy (deterministic) and for
the scenario's controller: the episode's return under the environment's
reward and the RMS position error over the run.
"""

from __future__ import annotations

import argparse
import time

import gymnasium
import numpy as np

import neurov
import neurov.gym  # noqa: F401  (registers neurov/Tracking-v0)


def evaluate(env: gymnasium.Env, policy, seed: int) -> tuple[float, float, int, str]:
    """Return, RMS position error [m], steps and how the episode ended."""
    obs, info = env.reset(seed=seed)
    total, errors = 0.0, []
    while True:
        obs, reward, terminated, truncated, info = env.step(policy(obs))
        total += reward
        errors.append(np.sum((info["eta_true"][:3] - info["eta_d"][:3]) ** 2))
        if terminated or truncated:
            return total, float(np.sqrt(np.mean(errors))), len(errors), "terminated" if terminated else "truncated"


def main() -> None:
    import torch
    from stable_baselines3 import PPO

    torch.set_num_threads(1)  # a 64-unit MLP: more threads only contend

    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--scenario", default="paper_fig3")
    p.add_argument("--timesteps", type=int, default=50_000)
    p.add_argument("--seed", type=int, default=0, help="PPO's seed")
    p.add_argument("--save", help="save the trained model here (.zip)")
    p.add_argument("--envs", type=int, default=0, help="train on this many envs of the vector env (0: one single env)")
    args = p.parse_args()

    env = gymnasium.make("neurov/Tracking-v0", scenario=args.scenario)
    if args.envs:
        from neurov.gym.sb3 import TrackingSB3VecEnv

        train_env: object = TrackingSB3VecEnv(args.envs, scenario=args.scenario)
    else:
        train_env = env
    model = PPO("MlpPolicy", train_env, seed=args.seed, verbose=0, device="cpu")
    t0 = time.perf_counter()
    model.learn(total_timesteps=args.timesteps)
    print(f"PPO: {args.timesteps} timesteps in {time.perf_counter() - t0:.0f} s")
    if args.save:
        model.save(args.save)

    # Evaluated with the scenario's noise seed, so the scenario's controller
    # below sees the same noise.
    scenario = env.unwrapped.scenario
    ret, rms, steps, end = evaluate(env, lambda o: model.predict(o, deterministic=True)[0], scenario.seed)
    print(f"PPO policy: RMS position error over the run {rms:.3f} m ({steps} steps, {end}; return {ret:.1f})")
    m = neurov.simulate(scenario).metrics(after=0.0)
    print(f"the scenario's controller ({scenario.controller.type}): RMS position error over the run "
          f"{m['rmse_position_m']:.3f} m (neurov.simulate)")


if __name__ == "__main__":
    main()
