"""Where to put the centres of an RBF network.

The paper says its centres were "uniformly spaced in the state space". In the
controller's 24-dimensional input space a full grid is out of reach (even 2
points per input is 2**24 = 16.7 million centres), so neurov offers:

* :func:`grid` - a uniform grid over a few chosen inputs, the others held at a
  fixed value (for example a grid over position and heading only);
* :func:`sobol` and :func:`latin_hypercube` - N quasi-uniform points filling a
  box in all inputs, seeded and reproducible (``scipy.stats.qmc``).

Every function returns an ``(N, n_inputs)`` float64 array for
:class:`neurov.RbfNetwork`.
"""

from __future__ import annotations

import itertools
import math
import warnings
from collections.abc import Mapping

import numpy as np
from numpy.typing import ArrayLike, NDArray

from neurov import _core

__all__ = ["INPUT_NAMES", "check_count", "grid", "latin_hypercube", "sobol"]

_DOF = ("u", "v", "w", "p", "q", "r")
_POSE = ("x", "y", "z", "phi", "theta", "psi")
#: Names of the NN controller's 24 inputs, x = [nu_r_dot; nu_r; nu; eta].
INPUT_NAMES: tuple[str, ...] = (
    tuple(f"nu_r_dot_{d}" for d in _DOF)
    + tuple(f"nu_r_{d}" for d in _DOF)
    + tuple(f"nu_{d}" for d in _DOF)
    + tuple(f"eta_{d}" for d in _POSE)
)


def check_count(n: int, name: str = "n") -> None:
    """Refuses a number of centres above ``neurov.MAX_CENTRES`` (the C++
    network's ``kMaxCentres``, 65536) before any centre is made: 10^8 of them
    would need 19 GB for the centres alone."""
    if n > _core.MAX_CENTRES:
        raise ValueError(f"argument '{name}': {n} centres, more than the {_core.MAX_CENTRES} "
                         "a network takes (neurov.MAX_CENTRES)")


def _index(key: int | str, n_inputs: int) -> int:
    if isinstance(key, str):
        if key not in INPUT_NAMES:
            raise ValueError(f"unknown input name {key!r}; expected one of {INPUT_NAMES}")
        key = INPUT_NAMES.index(key)
    if not 0 <= key < n_inputs:
        raise ValueError(f"input index {key} out of range 0..{n_inputs - 1}")
    return key


def grid(
    axes: Mapping[int | str, tuple[float, float, int]],
    n_inputs: int = 24,
    fill: float | ArrayLike = 0.0,
) -> NDArray[np.float64]:
    """A uniform grid over chosen inputs.

    ``axes`` maps an input (index, or a name from :data:`INPUT_NAMES`) to
    ``(low, high, count)``; every other input is held at ``fill`` (a number or
    an ``(n_inputs,)`` array). The result has ``prod(count)`` rows.

    >>> grid({"eta_x": (-10, 10, 5), "eta_y": (-10, 10, 5)}).shape
    (25, 24)
    """
    if not axes:
        raise ValueError("argument 'axes' must name at least one input")
    base = np.broadcast_to(np.asarray(fill, dtype=np.float64), (n_inputs,)).copy()
    if not np.all(np.isfinite(base)):
        raise ValueError("argument 'fill' must be finite")
    columns: list[int] = []
    for key, spec in axes.items():
        low, high, count = spec
        if int(count) != count or count < 1:
            raise ValueError(f"axis {key!r}: count must be a positive integer, got {count!r}")
        if not (np.isfinite(low) and np.isfinite(high) and high >= low):
            raise ValueError(f"axis {key!r}: expected finite low <= high, got ({low}, {high})")
        columns.append(_index(key, n_inputs))
    if len(set(columns)) != len(columns):
        raise ValueError("argument 'axes' names the same input twice")
    check_count(math.prod(int(count) for _, _, count in axes.values()), "axes")
    values = [np.linspace(low, high, int(count)) for low, high, count in axes.values()]
    points = np.array(list(itertools.product(*values)), dtype=np.float64)
    out = np.tile(base, (len(points), 1))
    out[:, columns] = points
    return out


def _box(low: ArrayLike, high: ArrayLike, n_inputs: int) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    lo = np.asarray(low, dtype=np.float64)
    hi = np.asarray(high, dtype=np.float64)
    if lo.ndim == 0 and hi.ndim == 0:
        lo = np.full(n_inputs, lo)
    try:
        lo, hi = np.broadcast_arrays(lo, hi)
    except ValueError:
        raise ValueError(
            f"arguments 'low' and 'high' must have the same length, got {lo.shape} and {hi.shape}"
        ) from None
    if lo.ndim != 1:
        raise ValueError("arguments 'low' and 'high' must be numbers or 1-D arrays")
    if not (np.all(np.isfinite(lo)) and np.all(np.isfinite(hi))):
        raise ValueError("arguments 'low' and 'high' must be finite")
    if np.any(hi < lo):
        raise ValueError("argument 'high' must be >= 'low' in every input")
    return lo.astype(np.float64), hi.astype(np.float64)


def _scale(unit: NDArray[np.float64], lo: NDArray[np.float64], hi: NDArray[np.float64]) -> NDArray[np.float64]:
    return np.asarray(lo + unit * (hi - lo), dtype=np.float64)


def sobol(n: int, low: ArrayLike, high: ArrayLike, seed: int = 0, n_inputs: int = 24) -> NDArray[np.float64]:
    """``n`` scrambled Sobol points in the box ``[low, high]`` (one bound per
    input, or one number for all ``n_inputs``). Powers of two give the best
    balance; other ``n`` take the first ``n`` points of the sequence."""
    lo, hi = _box(low, high, n_inputs)
    if int(n) != n or n < 1:
        raise ValueError(f"argument 'n' must be a positive integer, got {n!r}")
    check_count(int(n))
    from scipy.stats import qmc  # here: scipy.stats costs about 75 MB and a second to import

    sampler = qmc.Sobol(d=len(lo), scramble=True, rng=np.random.default_rng(seed))
    with warnings.catch_warnings():
        # scipy warns when n is not a power of two; the points are still valid.
        warnings.simplefilter("ignore", UserWarning)
        unit = sampler.random(int(n))
    return _scale(unit, lo, hi)


def latin_hypercube(
    n: int, low: ArrayLike, high: ArrayLike, seed: int = 0, n_inputs: int = 24
) -> NDArray[np.float64]:
    """``n`` Latin-hypercube points in the box ``[low, high]`` (one bound per
    input, or one number for all ``n_inputs``), seeded."""
    lo, hi = _box(low, high, n_inputs)
    if int(n) != n or n < 1:
        raise ValueError(f"argument 'n' must be a positive integer, got {n!r}")
    check_count(int(n))
    from scipy.stats import qmc

    sampler = qmc.LatinHypercube(d=len(lo), rng=np.random.default_rng(seed))
    return _scale(sampler.random(int(n)), lo, hi)

