"""neurov.laws.centres: where an RBF network's centres go (a grid over a few inputs,
or quasi-random points filling a box)."""

from __future__ import annotations

import numpy as np
import pytest

import neurov
from neurov import centres

# ------------------------------------------------------------------- names


def test_input_names_follow_the_order_of_x() -> None:
    names = centres.INPUT_NAMES
    assert len(names) == 24
    assert len(set(names)) == 24
    # x = [nu_r_dot; nu_r; nu; eta]
    assert names[0] == "nu_r_dot_u"
    assert names[5] == "nu_r_dot_r"
    assert names[6] == "nu_r_u"
    assert names[12] == "nu_u"
    assert names[17] == "nu_r"
    assert names[18:] == ("eta_x", "eta_y", "eta_z", "eta_phi", "eta_theta", "eta_psi")


# -------------------------------------------------------------------- grid


def test_grid_shape_and_values_over_named_inputs() -> None:
    g = centres.grid({"eta_x": (-10, 10, 5), "eta_y": (-4, 4, 3)})
    assert g.shape == (15, 24)
    assert g.dtype == np.float64
    ix, iy = centres.INPUT_NAMES.index("eta_x"), centres.INPUT_NAMES.index("eta_y")
    # Every combination once.
    pairs = {(float(a), float(b)) for a, b in g[:, [ix, iy]]}
    assert pairs == {(x, y) for x in np.linspace(-10, 10, 5) for y in np.linspace(-4, 4, 3)}
    others = np.delete(g, [ix, iy], axis=1)
    np.testing.assert_array_equal(others, 0.0)


def test_grid_by_index_with_fill_vector_and_custom_input_count() -> None:
    fill = np.arange(6, dtype=float)
    g = centres.grid({1: (0.0, 1.0, 2), 4: (-1.0, -1.0, 1)}, n_inputs=6, fill=fill)
    assert g.shape == (2, 6)
    np.testing.assert_array_equal(g[:, 1], [0.0, 1.0])
    np.testing.assert_array_equal(g[:, 4], [-1.0, -1.0])
    np.testing.assert_array_equal(g[:, [0, 2, 3, 5]], np.tile(fill[[0, 2, 3, 5]], (2, 1)))


def test_grid_centres_build_a_controller_network() -> None:
    g = centres.grid({"eta_x": (-2, 2, 3), "eta_psi": (-np.pi, np.pi, 4)})
    net = neurov.RbfNetwork(g, 30.0)
    assert net.n_centres == 12
    assert net.n_inputs == 24


@pytest.mark.parametrize(
    ("axes", "kwargs", "match"),
    [
        ({}, {}, "axes"),
        ({"eta_q": (0, 1, 2)}, {}, "unknown input name 'eta_q'"),
        ({24: (0, 1, 2)}, {}, "out of range"),
        ({-1: (0, 1, 2)}, {}, "out of range"),
        ({"eta_x": (0, 1, 0)}, {}, "count"),
        ({"eta_x": (0, 1, 2.5)}, {}, "count"),
        ({"eta_x": (1, 0, 2)}, {}, "low <= high"),
        ({"eta_x": (0, np.inf, 2)}, {}, "finite"),
        ({"eta_x": (0, 1, 2), 18: (0, 1, 2)}, {}, "same input twice"),
        ({"eta_x": (0, 1, 2)}, {"fill": np.nan}, "fill"),
        ({3: (0, 1, 2)}, {"n_inputs": 3}, "out of range"),
    ],
)
def test_grid_errors_say_what_is_wrong(axes: dict, kwargs: dict, match: str) -> None:
    with pytest.raises(ValueError, match=match):
        centres.grid(axes, **kwargs)


# ------------------------------------------------ sobol and latin hypercube

SAMPLERS = [centres.sobol, centres.latin_hypercube]


@pytest.mark.parametrize("sampler", SAMPLERS)
@pytest.mark.parametrize("n", [1, 7, 64])
def test_sampler_shape_and_bounds_per_input(sampler, n: int) -> None:  # type: ignore[no-untyped-def]
    low = np.linspace(-5, 0, 24)
    high = low + np.linspace(0.1, 10, 24)
    pts = sampler(n, low, high, seed=3)
    assert pts.shape == (n, 24)
    assert pts.dtype == np.float64
    assert np.all(pts >= low)
    assert np.all(pts <= high)


@pytest.mark.parametrize("sampler", SAMPLERS)
def test_sampler_fills_the_box(sampler) -> None:  # type: ignore[no-untyped-def]
    # 256 points in 3 inputs: every input's range is used, not a corner of it.
    pts = sampler(256, [0.0, -1.0, 10.0], [1.0, 1.0, 20.0], seed=1)
    span = pts.max(axis=0) - pts.min(axis=0)
    np.testing.assert_array_less([0.95, 1.9, 9.5], span)
    # A Latin hypercube / balanced Sobol set puts ~1/4 of the points in each quarter.
    quarter = np.sum(pts[:, 0] < 0.25)
    assert 48 <= quarter <= 80


@pytest.mark.parametrize("sampler", SAMPLERS)
def test_sampler_scalar_bounds_broadcast(sampler) -> None:  # type: ignore[no-untyped-def]
    pts = sampler(16, -2.0, [1.0, 2.0, 3.0], seed=0)
    assert pts.shape == (16, 3)
    assert np.all(pts >= -2.0)
    assert np.all(pts <= [1.0, 2.0, 3.0])


@pytest.mark.parametrize("sampler", SAMPLERS)
def test_sampler_is_reproducible_with_a_seed_and_differs_with_another(sampler) -> None:  # type: ignore[no-untyped-def]
    a = sampler(32, -np.ones(24), np.ones(24), seed=11)
    b = sampler(32, -np.ones(24), np.ones(24), seed=11)
    c = sampler(32, -np.ones(24), np.ones(24), seed=12)
    np.testing.assert_array_equal(a, b)
    assert np.abs(a - c).max() > 0.1


def test_sobol_with_a_non_power_of_two_raises_no_warning() -> None:
    # pytest runs with filterwarnings = error: scipy's balance warning would fail here.
    pts = centres.sobol(10, 0.0, 1.0, seed=0, n_inputs=1)
    assert pts.shape == (10, 1)
    assert np.all((pts >= 0.0) & (pts <= 1.0))


@pytest.mark.parametrize("sampler", SAMPLERS)
@pytest.mark.parametrize(
    ("args", "match"),
    [
        ((0, 0.0, 1.0), "'n'"),
        ((-3, 0.0, 1.0), "'n'"),
        ((2.5, 0.0, 1.0), "'n'"),
        ((4, [0.0, 1.0], [1.0, 0.5]), "'high' must be >= 'low'"),
        ((4, [0.0, np.nan], 1.0), "finite"),
        ((4, 0.0, np.inf), "finite"),
        ((4, np.zeros((2, 2)), 1.0), "1-D"),
    ],
)
def test_sampler_errors_say_what_is_wrong(sampler, args: tuple, match: str) -> None:  # type: ignore[no-untyped-def]
    with pytest.raises(ValueError, match=match):
        sampler(*args)
