"""Whether an NN controller's network is a network: the rank of its basis
along a run. With the paper's width (30) on inputs in SI units every basis
value along paper_fig3 lies between 0.85 and 1.00 and the second singular
value of the basis matrix is 2 % of the first: the "network" is one adaptive
bias per DOF. This module records g(x) at every control step of a run and
reports the singular values of the (steps x centres) matrix.

The C++ loop does not log the basis, so a recorded run goes through the
Python loop with the same C++ controller (the numbers are the same; the run
takes about 2.6 times as long), which is why studies ask for it
(``[diagnostics] basis_rank = true``; every tuning's verdict does)."""

from __future__ import annotations

import math
from typing import Any

import numpy as np

__all__ = ["BASIS_COLUMNS", "BasisRecorder", "basis_columns", "rank_diagnostic"]

#: The runs table's columns of the diagnostic (NaN for the other controllers).
BASIS_COLUMNS = ("nn_basis_min", "nn_basis_max", "nn_basis_sigma2_ratio", "nn_basis_effective_rank")


class BasisRecorder:
    """A built-in NN controller stepped from Python, its basis g(x) kept
    after every step (the controller's ``basis``: of the last step's input)."""

    def __init__(self, controller: Any) -> None:
        self.controller = controller
        self.rows: list[np.ndarray] = []
        self.norms: list[float] = []

    def reset(self) -> None:
        self.rows.clear()
        self.norms.clear()

    @property
    def s(self) -> Any:
        # The Python loop logs a controller's s when it has one, as the C++ loop does.
        return self.controller.s

    def step(self, eta: Any, nu: Any, eta_d: Any, eta_d_dot: Any, eta_d_ddot: Any) -> Any:
        tau = self.controller.step(eta, nu, eta_d, eta_d_dot, eta_d_ddot)
        self.rows.append(np.array(self.controller.basis, dtype=np.float64))
        self.norms.append(float(self.controller.weight_norm))
        return tau

    def matrix(self) -> np.ndarray:
        return np.vstack(self.rows) if self.rows else np.zeros((0, 0))

    def log_weight_norm(self, result: Any) -> Any:
        """`result` with the adaptive norm the C++ loop logs (||W|| after each
        step): the Python loop cannot know a controller's weights and logs 0."""
        if len(self.norms) == len(result.adaptive_norm):
            result.adaptive_norm = np.asarray(self.norms)
        return result


def rank_diagnostic(basis: np.ndarray) -> dict[str, Any]:
    """Of a (steps x centres) basis matrix: its smallest and largest value,
    its singular values (largest first), sigma_2 / sigma_1 and the effective
    rank exp(H(p)), p the singular values divided by their sum (Roy and
    Vetterli, 2007): 1 for a rank-one matrix, the number of centres when all
    singular values are equal."""
    g = np.asarray(basis, dtype=np.float64)
    if g.size == 0 or not np.all(np.isfinite(g)):
        return {"min": math.nan, "max": math.nan, "singular_values": [], "sigma2_ratio": math.nan,
                "effective_rank": math.nan}
    s = np.linalg.svd(g, compute_uv=False)
    total = float(s.sum())
    if total <= 0.0:
        return {"min": float(g.min()), "max": float(g.max()), "singular_values": s.tolist(),
                "sigma2_ratio": math.nan, "effective_rank": 0.0}
    p = s[s > 0] / total
    return {"min": float(g.min()), "max": float(g.max()), "singular_values": s.tolist(),
            "sigma2_ratio": float(s[1] / s[0]) if s.size > 1 else 0.0,
            "effective_rank": float(np.exp(-np.sum(p * np.log(p))))}


def basis_columns(basis: np.ndarray) -> dict[str, float]:
    """The diagnostic as the runs table's columns."""
    d = rank_diagnostic(basis)
    return {"nn_basis_min": d["min"], "nn_basis_max": d["max"], "nn_basis_sigma2_ratio": d["sigma2_ratio"],
            "nn_basis_effective_rank": d["effective_rank"]}
