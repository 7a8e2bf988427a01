"""Least squares held as per-block normal equations, so that an estimate
and its block bootstrap are sums over the same blocks.

A block is a stretch of consecutive samples (a few seconds) inside one
segment of a log: residuals coloured by an estimator, a delay or the
closed loop are correlated within a block, and the blocks are resampled
whole (Kuensch's moving-block idea, here on non-overlapping blocks).

With few blocks the bootstrap's spread is short of the estimate's: it is
the spread of G block contributions, (G - 1) / G of their unbiased variance,
and itself estimated from G of them. So the intervals are the bootstrap's
percentiles moved away from the estimate by :func:`small_sample_scale`, the
cluster-robust correction sqrt(G / (G - 1)) and the t quantile with G - 1
degrees of freedom in place of the normal one (Cameron and Miller, "A
practitioner's guide to cluster-robust inference", J. Human Resources 50(2),
2015, sections VI.B-C)."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray
from scipy.stats import norm, t

__all__ = ["Blocks", "block_ids", "small_sample_scale"]

Array = NDArray[np.float64]


def block_ids(segment_of_row: NDArray[np.int64], times: Array, block_s: float) -> NDArray[np.int64]:
    """A block number for each row: rows of one segment cut every `block_s` seconds."""
    ids = np.empty(len(times), dtype=np.int64)
    next_id = 0
    for seg in np.unique(segment_of_row):
        rows = np.flatnonzero(segment_of_row == seg)
        local = np.floor((times[rows] - times[rows[0]]) / block_s).astype(np.int64)
        ids[rows] = next_id + local
        next_id += int(local.max()) + 1
    # Renumber densely (an empty block number is no block).
    _, dense = np.unique(ids, return_inverse=True)
    return dense.astype(np.int64)


def small_sample_scale(n_blocks: int, level: float = 0.95) -> float:
    """The factor by which the bootstrap percentiles' distances from the
    estimate are stretched for `n_blocks` (G >= 2) blocks:
    sqrt(G / (G - 1)) t_{G-1} / z at the two-sided `level` (1.17 for 12
    blocks, 1.08 for 24, toward 1 as G grows)."""
    if n_blocks < 2:
        raise ValueError(f"n_blocks: expected at least 2 blocks, got {n_blocks}")
    if not 0 < level < 1:
        raise ValueError(f"level: expected a probability in (0, 1), got {level}")
    q = 0.5 + 0.5 * level
    return float(np.sqrt(n_blocks / (n_blocks - 1)) * t.ppf(q, n_blocks - 1) / norm.ppf(q))


@dataclass(frozen=True)
class Blocks:
    """G_b = A_b^T A_b and h_b = A_b^T b_b of each block b (p unknowns);
    with `keep`, the solutions are the first `keep` unknowns (the rest are
    nuisance unknowns estimated with them, an estimator's gains)."""

    gram: Array  #: (B, p, p)
    rhs: Array  #: (B, p)
    keep: int | None = None

    @staticmethod
    def from_rows(a: Array, b: Array, ids: NDArray[np.int64]) -> Blocks:
        n = int(ids.max()) + 1 if len(ids) else 0
        p = a.shape[1]
        gram = np.zeros((n, p, p))
        rhs = np.zeros((n, p))
        for k in range(n):
            rows = ids == k
            gram[k] = a[rows].T @ a[rows]
            rhs[k] = a[rows].T @ b[rows]
        return Blocks(gram, rhs)

    @property
    def count(self) -> int:
        return int(self.gram.shape[0])

    def solve(self, weights: Array | None = None) -> Array:
        w = np.ones(self.count) if weights is None else weights
        x = np.asarray(np.linalg.solve(np.tensordot(w, self.gram, 1), np.tensordot(w, self.rhs, 1)),
                       dtype=np.float64)
        return x if self.keep is None else x[:self.keep]

    def bootstrap(self, replicates: int, seed: int) -> Array:
        """(replicates, p) solutions with the blocks drawn with replacement;
        a draw whose normal matrix is singular is drawn again."""
        rng = np.random.default_rng(seed)
        out = np.empty((replicates, self.gram.shape[1] if self.keep is None else self.keep))
        k = 0
        tries = 0
        while k < replicates:
            tries += 1
            if tries > 20 * replicates:
                raise np.linalg.LinAlgError("the resampled normal equations are singular")
            w = np.bincount(rng.integers(0, self.count, self.count), minlength=self.count).astype(float)
            try:
                out[k] = self.solve(w)
            except np.linalg.LinAlgError:
                continue
            k += 1
        return out
