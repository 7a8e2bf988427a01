"""neurov.RbfNetwork (eq. 30): g_j(x) = exp(-||x_hat - xi_j||^2 / (2 sigma_j^2)),
output W g(x), x_hat = (x - input_offset) * input_scale; against numpy."""

from __future__ import annotations

import numpy as np
import pytest

import neurov


def numpy_basis(
    centres: np.ndarray, widths: np.ndarray, x: np.ndarray, offset: np.ndarray | None = None, scale: np.ndarray | None = None
) -> np.ndarray:
    xh = x.copy()
    if offset is not None:
        xh = xh - offset
    if scale is not None:
        xh = xh * scale
    d2 = np.sum((centres - xh) ** 2, axis=1)
    return np.exp(-d2 / (2.0 * widths**2))


def test_basis_and_output_match_numpy(rng: np.random.Generator) -> None:
    for k in range(30):
        n_in, n_c = 1 + k % 24, 1 + (7 * k) % 40
        x = rng.uniform(-3, 3, n_in)
        offset = rng.uniform(-0.5, 0.5, n_in)
        scale = rng.uniform(0.5, 2.0, n_in)
        c = (x - offset) * scale + rng.uniform(-1, 1, (n_c, n_in))
        widths = rng.uniform(0.5, 3.0, n_c)
        w = rng.uniform(-10, 10, (6, n_c))
        net = neurov.RbfNetwork(c, widths, offset, scale)
        net.weights = w
        assert (net.n_inputs, net.n_centres) == (n_in, n_c)
        g = numpy_basis(c, widths, x, offset, scale)
        np.testing.assert_allclose(net.basis(x), g, rtol=1e-12, atol=1e-14)
        np.testing.assert_allclose(net.output(x), w @ g, rtol=1e-12, atol=1e-12)
        np.testing.assert_array_equal(net.weights, w)
        np.testing.assert_array_equal(net.centres, c)
        np.testing.assert_array_equal(net.widths, widths)
        np.testing.assert_array_equal(net.input_offset, offset)
        np.testing.assert_array_equal(net.input_scale, scale)


def test_scalar_width_is_shared_and_weights_start_at_zero() -> None:
    c = np.array([[0.0, 0.0], [3.0, 4.0]])
    net = neurov.RbfNetwork(c, 5.0)
    np.testing.assert_array_equal(net.widths, [5.0, 5.0])
    np.testing.assert_array_equal(net.weights, np.zeros((6, 2)))
    np.testing.assert_array_equal(net.input_offset, [0.0, 0.0])
    np.testing.assert_array_equal(net.input_scale, [1.0, 1.0])
    # At centre 0 its basis is 1; centre 1 is exactly one width (5) away.
    np.testing.assert_allclose(net.basis([0.0, 0.0]), [1.0, np.exp(-0.5)], rtol=1e-15)
    np.testing.assert_array_equal(net.output([0.0, 0.0]), np.zeros(6))


def test_weights_assignment_checks_shape_and_values() -> None:
    net = neurov.RbfNetwork(np.zeros((3, 2)), 1.0)
    with pytest.raises(ValueError, match=r"'weights' must have shape \(6, 3\)"):
        net.weights = np.zeros((6, 4))
    bad = np.zeros((6, 3))
    bad[2, 1] = np.nan
    with pytest.raises(ValueError, match="'weights' must be finite"):
        net.weights = bad
    np.testing.assert_array_equal(net.weights, np.zeros((6, 3)))


@pytest.mark.parametrize(
    ("x", "error", "match"),
    [
        (np.zeros(3), ValueError, r"'x' must have shape \(2,\)"),
        (np.array([0.0, np.nan]), ValueError, "'x' must be finite"),
        (np.array([np.inf, 0.0]), ValueError, "'x' must be finite"),
        (None, TypeError, "'x'"),
        (np.array(["a", "b"]), TypeError, "'x'"),
    ],
)
def test_bad_x_is_refused_naming_it(x: object, error: type, match: str) -> None:
    net = neurov.RbfNetwork(np.zeros((3, 2)), 1.0)
    for method in (net.basis, net.output):
        with pytest.raises(error, match=match):
            method(x)


def _nan_centres() -> np.ndarray:
    c = np.zeros((3, 2))
    c[1, 0] = np.nan
    return c


@pytest.mark.parametrize(
    ("centres", "width", "extra", "match"),
    [
        (np.zeros((0, 2)), 1.0, {}, "centres"),
        (np.zeros((3, 0)), 1.0, {}, "centres"),
        (np.zeros(3), 1.0, {}, "centres"),
        (_nan_centres(), 1.0, {}, "'centres' must be finite"),
        (np.zeros((3, 2)), 0.0, {}, "widths"),
        (np.zeros((3, 2)), -1.0, {}, "widths"),
        (np.zeros((3, 2)), np.array([1.0, 0.0, 1.0]), {}, r"widths\[1\] = 0"),
        (np.zeros((3, 2)), np.array([1.0, 1.0, -2.0]), {}, r"widths\[2\] = -2"),
        (np.zeros((3, 2)), np.array([1.0, 1.0]), {}, r"'width' must have shape \(3,\)"),
        (np.zeros((3, 2)), np.nan, {}, "'width' must be finite"),
        (np.zeros((3, 2)), 1.0, {"input_offset": np.zeros(3)}, "'input_offset'"),
        (np.zeros((3, 2)), 1.0, {"input_scale": np.array([1.0, 0.0])}, "input_scale"),
    ],
)
def test_invalid_network_names_the_field(centres: np.ndarray, width: object, extra: dict, match: str) -> None:
    with pytest.raises(ValueError, match=match):
        neurov.RbfNetwork(centres, width, **extra)
