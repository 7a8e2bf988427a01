"""TrackingTask's one-pass step (observe_outcome, the single env's path)
against its two-call form (observe then outcome, the vector env's path),
and the per-K buffers it reuses never showing through what it returns."""

from __future__ import annotations

import numpy as np
from neurov.gym import TrackingEnv


def _rows(rng: np.random.Generator, k: int) -> list[np.ndarray]:
    # eta, nu, eta_d, eta_d_dot, eta_d_ddot, eta_true: angles beyond pi so that the wrap matters.
    return [rng.uniform(-7.0, 7.0, (k, 6)) for _ in range(6)]


def test_one_pass_equals_observe_then_outcome_to_the_bit() -> None:
    task = TrackingEnv("paper_fig3").task
    rng = np.random.default_rng(3)
    for k in (1, 5):
        eta, nu, eta_d, dd, ddd, eta_true = _rows(rng, k)
        eta_true[-1, 0] = 1e6  # one row outside the box: terminated, charged for the steps left
        a = rng.uniform(-1.0, 1.0, (k, task.action_shape[0]))
        done = np.arange(k) % 2 == 0
        steps_left = np.arange(k) * 10
        fused = task.observe_outcome(eta, nu, eta_d, dd, ddd, eta_true, a, False, done, steps_left)
        apart = (task.observe(eta, nu, eta_d, dd, ddd), *task.outcome(eta_true, eta_d, a, False, done, steps_left))
        for got, want in zip(fused, apart, strict=True):
            np.testing.assert_array_equal(got, want)
        assert fused[2][-1] and not fused[3][-1] and fused[4][-1]


def test_returned_arrays_are_not_the_reused_buffers() -> None:
    env = TrackingEnv("paper_fig3")
    obs0, _ = env.reset(seed=0)
    first = env.step(np.full(6, 0.5, dtype=np.float32))
    kept = [obs0.copy(), first[0].copy()]
    for _ in range(3):
        env.step(np.full(6, -0.5, dtype=np.float32))
    np.testing.assert_array_equal(obs0, kept[0])
    np.testing.assert_array_equal(first[0], kept[1])
