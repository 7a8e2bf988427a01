"""The Hypothesis settings and strategies the property tests share
(test_properties.py, test_model_properties.py)."""

from __future__ import annotations

import numpy as np
from hypothesis import HealthCheck, settings
from hypothesis import strategies as st

SETTINGS = settings(max_examples=60, deadline=None, suppress_health_check=[HealthCheck.too_slow])
FEW = settings(max_examples=15, deadline=None, suppress_health_check=[HealthCheck.too_slow])

ARGS = ("eta", "nu", "eta_d", "eta_d_dot", "eta_d_ddot")


def finite(lo: float, hi: float) -> st.SearchStrategy[float]:
    return st.floats(lo, hi, allow_nan=False, allow_infinity=False)


angle = finite(-np.pi, np.pi)
# Pitch away from the singularity by at least 0.05 rad (|1/cos| <= 20).
pitch = finite(-np.pi / 2 + 0.05, np.pi / 2 - 0.05)


@st.composite
def poses(draw: st.DrawFn, pitch: st.SearchStrategy[float] = pitch) -> np.ndarray:
    xyz = [draw(finite(-100, 100)) for _ in range(3)]
    return np.array([*xyz, draw(angle), draw(pitch), draw(angle)])


def vectors(n: int, lo: float, hi: float) -> st.SearchStrategy[np.ndarray]:
    return st.lists(finite(lo, hi), min_size=n, max_size=n).map(np.array)


velocities = vectors(6, -2.0, 2.0)
