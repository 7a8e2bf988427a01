"""The NN controller's step (eq. 30, 35, 37) against the numpy reference of
controller_reference.py: the weights from before the update, per-centre
learning rates, the robust modifications, the dead zone, reset and warm
start."""

from __future__ import annotations

from typing import Any

import numpy as np
import pytest

import reference_model as ref
from controller_reference import assert_step_matches, jac_dot, make_nn, nn_reference, random_case, random_state, tracking

Array = np.ndarray


def test_reference_jacobian_dot_is_the_derivative_of_the_reference_jacobian(rng: np.random.Generator) -> None:
    # The reference is a hand transcription too: check it before trusting it.
    for _ in range(30):
        eta = np.r_[rng.uniform(-5, 5, 3), rng.uniform(-np.pi, np.pi), rng.uniform(-1.2, 1.2), rng.uniform(-np.pi, np.pi)]
        nu = rng.uniform(-1, 1, 6)
        h = 1e-6
        eta_dot = ref.jacobian(eta) @ nu
        fd = (ref.jacobian(eta + h * eta_dot) - ref.jacobian(eta - h * eta_dot)) / (2 * h)
        np.testing.assert_allclose(jac_dot(eta, nu), fd, atol=1e-6 * (1 + np.abs(fd).max()))
        np.testing.assert_allclose(ref.jacobian(eta) @ ref.jacobian_inverse(eta), np.eye(6), atol=1e-12)


# ------------------------------------------------------------ NN step (eq. 35, 37)


def test_nn_step_matches_numpy_with_the_weights_from_before_the_update(rng: np.random.Generator) -> None:
    for _ in range(20):
        c = random_case(rng)
        ctl = make_nn(c)
        w = c.weights
        for _ in range(3):
            ex = nn_reference(c, w)
            tau = ctl.step(*c.args())
            assert_step_matches(ctl, tau, ex, w)
            # tau from the updated weights would be off by (W_new - W) g: far outside the tolerance.
            assert np.abs((ex.weights - w) @ ex.g).max() > 1e-6
            w = ex.weights
            for key, value in random_state(rng).items():
                setattr(c, key, value)


def test_per_centre_learning_rates(rng: np.random.Generator) -> None:
    for _ in range(10):
        c = random_case(rng)
        rates = rng.uniform(0, 3, len(c.widths))
        rates[1] = 0.0
        ctl = make_nn(c, learning_rates=rates)
        ex = nn_reference(c, c.weights, rates)
        assert_step_matches(ctl, ctl.step(*c.args()), ex, c.weights)
        np.testing.assert_array_equal(ctl.weights[:, 1], c.weights[:, 1])  # rate 0: frozen
        assert np.abs(nn_reference(c, c.weights).weights - ex.weights).max() > 1e-6


@pytest.mark.parametrize(
    ("modification", "gain", "low", "high", "unlike"),
    [
        # sigma leaks where the plain law does not;
        ("sigma", "sigma_m", 0.2, 2.0, lambda value: {}),
        # e-modification's leak scales with ||J^-1 s||, not a constant sigma_m = kappa.
        ("e_modification", "kappa", 0.1, 1.0, lambda value: {"modification": "sigma", "sigma_m": value}),
    ],
)
def test_leakage_modifications(
    rng: np.random.Generator, modification: str, gain: str, low: float, high: float, unlike: Any
) -> None:
    for _ in range(10):
        c = random_case(rng)
        value = float(rng.uniform(low, high))
        ctl = make_nn(c, modification=modification, **{gain: value})
        assert ctl.modification == modification
        ex = nn_reference(c, c.weights, modification=modification, **{gain: value})
        assert_step_matches(ctl, ctl.step(*c.args()), ex, c.weights)
        assert np.abs(nn_reference(c, c.weights, **unlike(value)).weights - ex.weights).max() > 1e-6


def test_projection_keeps_the_frobenius_norm_within_w_max(rng: np.random.Generator) -> None:
    for _ in range(10):
        c = random_case(rng)
        plain = nn_reference(c, c.weights)
        w_max = 0.5 * float(np.linalg.norm(plain.weights))
        ctl = make_nn(c, modification="projection", w_max=w_max)
        ex = nn_reference(c, c.weights, modification="projection", w_max=w_max)
        assert_step_matches(ctl, ctl.step(*c.args()), ex, c.weights)
        assert np.linalg.norm(ctl.weights) <= w_max * (1 + 1e-14)
        assert ctl.weight_norm == pytest.approx(w_max, rel=1e-14)
        # A bound the step does not reach changes nothing.
        loose = make_nn(c, modification="projection", w_max=4 * w_max)  # twice the plain norm
        loose.step(*c.args())
        np.testing.assert_allclose(loose.weights, plain.weights, rtol=0, atol=1e-12 * np.abs(plain.weights).max())


def test_dead_zone_stops_adaptation_while_s_is_small(rng: np.random.Generator) -> None:
    for _ in range(10):
        c = random_case(rng)
        s_norm = float(np.linalg.norm(tracking(c.eta, c.nu, c.eta_d, c.eta_d_dot, c.eta_d_ddot, c.lam).s))
        inside = make_nn(c, dead_zone=1.5 * s_norm)
        ex = nn_reference(c, c.weights, dead_zone=1.5 * s_norm)
        assert not ex.adapted
        assert_step_matches(inside, inside.step(*c.args()), ex, c.weights)
        np.testing.assert_array_equal(inside.weights, c.weights)
        outside = make_nn(c, dead_zone=0.5 * s_norm)
        ex = nn_reference(c, c.weights, dead_zone=0.5 * s_norm)
        assert ex.adapted
        assert_step_matches(outside, outside.step(*c.args()), ex, c.weights)


def test_reset_and_warm_start(rng: np.random.Generator) -> None:
    c = random_case(rng)
    ctl = make_nn(c)
    ctl.step(*c.args())
    assert np.abs(ctl.weights - c.weights).max() > 0
    ctl.reset()
    np.testing.assert_array_equal(ctl.weights, c.weights)
    ctl.weights = np.zeros_like(c.weights)
    assert ctl.weight_norm == 0.0
    with pytest.raises(ValueError, match="'weights'"):
        ctl.weights = np.zeros((6, len(c.widths) + 1))
