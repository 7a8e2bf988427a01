"""Times one neurov.gym.TrackingEnv.step from Python: every call timed on its
own (time.perf_counter_ns), random actions drawn beforehand, the episode reset
(untimed) when it ends. Prints the median, mean and percentiles in
microseconds.

    python bench/gym_step.py [--scenario paper_fig3] [--action body] [--steps 20000]
"""

from __future__ import annotations

import argparse
import json
import platform
import time

import numpy as np

from neurov.gym import TrackingEnv


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--scenario", default="paper_fig3")
    p.add_argument("--action", default="body", choices=["body", "thrusters"])
    p.add_argument("--steps", type=int, default=20000)
    p.add_argument("--repeats", type=int, default=5, help="runs of --steps; the median of their medians is reported")
    p.add_argument("--json", help="also write the figures to this file")
    args = p.parse_args()

    env = TrackingEnv(args.scenario, action=args.action)
    actions = np.random.default_rng(0).uniform(-1, 1, (args.steps, *env.action_space.shape)).astype(np.float32)
    medians = []
    samples = np.empty(args.steps)
    for _ in range(args.repeats):
        env.reset(seed=0)
        for k, a in enumerate(actions):
            t0 = time.perf_counter_ns()
            _, _, terminated, truncated, _ = env.step(a)
            samples[k] = time.perf_counter_ns() - t0
            if terminated or truncated:
                env.reset()
        medians.append(float(np.median(samples)))
    us = samples / 1e3
    out = {
        "scenario": args.scenario, "action": args.action, "steps": args.steps, "repeats": args.repeats,
        "median_us": float(np.median(medians)) / 1e3,
        "medians_us": [m / 1e3 for m in medians],
        "last_run": {"mean_us": float(us.mean()), "p90_us": float(np.percentile(us, 90)),
                     "p99_us": float(np.percentile(us, 99))},
        "python": platform.python_version(), "numpy": np.__version__,
    }
    print(f"TrackingEnv.step ({args.scenario}, action={args.action}): median {out['median_us']:.1f} us "
          f"(medians of {args.repeats} runs of {args.steps}: "
          f"{', '.join(f'{m:.1f}' for m in out['medians_us'])}); last run mean {us.mean():.1f}, "
          f"p90 {np.percentile(us, 90):.1f}, p99 {np.percentile(us, 99):.1f} us")
    if args.json:
        with open(args.json, "w") as f:
            json.dump(out, f, indent=2)


if __name__ == "__main__":
    main()
