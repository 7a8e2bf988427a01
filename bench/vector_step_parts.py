"""Where one step of a one-env TrackingVectorEnv goes, against the single
TrackingEnv in the same process: the compiled step_batch alone (threads=0,
the default, and threads=1), the single env's step and the vector env's step,
each the best of --repeats timings of --number calls (paper_fig3, zero
actions, episodes restarted between timings).

    python bench/vector_step_parts.py [--number 100] [--repeats 30] [--rounds 2]
"""

from __future__ import annotations

import argparse
import timeit

import numpy as np
from neurov.gym import TrackingEnv, TrackingVectorEnv


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--number", type=int, default=100, help="calls per timing (an episode has 1,250 steps)")
    p.add_argument("--repeats", type=int, default=30)
    p.add_argument("--rounds", type=int, default=2, help="times the four are timed, in turn")
    args = p.parse_args()
    vec = TrackingVectorEnv(1, "paper_fig3")
    single = TrackingEnv("paper_fig3")
    one, many = np.zeros(6, np.float32), np.zeros((1, 6), np.float32)
    core, batch, mask = vec.task.core, vec._batch, np.ones(1, bool)

    def restart() -> None:
        vec.reset(seed=0)
        single.reset(seed=0)

    parts = [("step_batch, threads=0", lambda: core.step_batch(batch, many, mask, 0)),
             ("step_batch, threads=1", lambda: core.step_batch(batch, many, mask, 1)),
             ("TrackingEnv.step", lambda: single.step(one)),
             ("TrackingVectorEnv.step, K = 1", lambda: vec.step(many))]
    for _ in range(args.rounds):
        for name, call in parts:
            best = min(timeit.repeat(call, setup=restart, number=args.number, repeat=args.repeats))
            print(f"{name:32s} {best / args.number * 1e6:6.1f} us")


if __name__ == "__main__":
    main()
