"""A random agent in neurov's Gymnasium environment: one episode of the
paper's Fig. 3 scenario with uniformly random normalised forces, beside one
with no force at all, and the top view of the random one's end.

    python examples/gym_random_agent.py [--scenario paper_fig3] [--seed 0] [--out random_agent.png]
"""

from __future__ import annotations

import argparse

import gymnasium
import numpy as np

import neurov.gym  # noqa: F401  (registers neurov/Tracking-v0)


def episode(env: gymnasium.Env, seed: int, policy: str) -> tuple[int, float, str, dict]:
    obs, info = env.reset(seed=seed)
    env.action_space.seed(seed)
    total, steps = 0.0, 0
    while True:
        action = env.action_space.sample() if policy == "random" else np.zeros(env.action_space.shape, np.float32)
        obs, reward, terminated, truncated, info = env.step(action)
        total += reward
        steps += 1
        if terminated or truncated:
            return steps, total, "terminated" if terminated else "truncated", info


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--scenario", default="paper_fig3")
    p.add_argument("--seed", type=int, default=0)
    p.add_argument("--out", help="save the random episode's last frame (PNG) here")
    args = p.parse_args()

    env = gymnasium.make("neurov/Tracking-v0", scenario=args.scenario, render_mode="rgb_array")
    print(f"{args.scenario}: observation {env.observation_space.shape}, action {env.action_space.shape}, "
          f"action scale (+1) {np.round(env.unwrapped.action_scale[0], 1).tolist()}")
    for policy in ("random", "zero"):
        steps, total, end, info = episode(env, args.seed, policy)
        error = np.linalg.norm(info["eta_true"][:3] - info["eta_d"][:3])
        print(f"{policy:>6}: {steps} steps, {end} at t = {info['t']:.1f} s, return {total:.1f}, "
              f"final position error {error:.2f} m, clipped actions {info['action_clips']}")
        if policy == "random" and args.out:
            import matplotlib.pyplot as plt

            plt.imsave(args.out, env.render())
            print(f"top view: {args.out}")
    env.close()


if __name__ == "__main__":
    main()
