"""The longest step neurov integrates (10 s, neurov::kMaxStep in
core/validation.hpp): a longer one is a ValueError naming dt and the bound,
not finite nonsense (rk4_step gave 1e43 after 1e6 s) or a non-finite-input
error, and changes nothing."""
from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

import neurov
from neurov.config.reading import load_scenario

TOO_LONG = [10.000001, 10.5, 1e6, 1e30]


@pytest.mark.parametrize("dt", TOO_LONG)
def test_rk4_step_above_the_maximum_names_the_bound(nerov: neurov.Vehicle, dt: float) -> None:
    eta, nu = np.full(6, 0.1), np.full(6, 0.2)
    with pytest.raises(ValueError, match=r"argument 'dt' must be > 0 and <= 10 s .* got "):
        neurov.rk4_step(nerov, eta, nu, np.array([100.0, 0, 50, 0, 0, 5]), dt)


def test_rk4_step_of_the_maximum_is_taken(nerov: neurov.Vehicle) -> None:
    eta, nu = neurov.rk4_step(nerov, np.zeros(6), np.zeros(6), np.zeros(6), 10.0)
    assert np.all(np.isfinite(eta)) and np.all(np.isfinite(nu))


@pytest.mark.parametrize("dt", TOO_LONG)
def test_reference_step_above_the_maximum_names_the_bound_and_changes_nothing(dt: float) -> None:
    model = neurov.ReferenceModel(np.ones(6), np.full(6, 0.25))
    r = np.array([1.0, 0, 0, 0, 0, 0])
    model.step(r, 0.2)
    twin = neurov.ReferenceModel(np.ones(6), np.full(6, 0.25))
    twin.step(r, 0.2)
    with pytest.raises(ValueError, match=r"argument 'dt' must be > 0 and <= 10 s"):
        model.step(r, dt)
    for a, b in zip(model.step(r, 0.2), twin.step(r, 0.2)):
        np.testing.assert_array_equal(a, b)


def test_closed_loop_with_a_control_period_above_the_maximum_names_dt() -> None:
    shipped = load_scenario(Path(neurov.__file__).with_name("scenarios") / "nerov_square.toml")
    with pytest.raises(ValueError, match="dt"):
        neurov.simulate(shipped.replace(dt=12.0, duration=60.0))
