"""The statistics of a verdict, for every scenario with more than one plant:
each controller's median with a distribution-free confidence interval, and,
against a reference controller on the same plants, the median of the paired
ratios with its interval, the count of plants where the controller is
better, and a Wilcoxon signed-rank p-value corrected by Holm's method over
all the comparisons of the table. Ranks come from the paired comparisons.

Why order statistics: the interval ``[x[l], x[n+1-l]]`` between the l-th
smallest and the l-th largest of n values covers the true median with
probability ``1 - 2 P(B <= l - 1)``, ``B ~ Bin(n, 1/2)``, for any continuous
distribution; it needs no model and, unlike a bootstrap
percentile interval, does not cover too little at n ~ 20. Below six plants
no such interval reaches 95 %: the columns say "n/a".

SciPy is imported inside the functions that need it, so that ``import
neurov`` does not load scipy.stats.
"""

from __future__ import annotations

import functools
import math
from collections.abc import Sequence

import numpy as np

__all__ = ["LEVEL", "holm", "median_ci", "order_statistic_rank", "paired_ranks", "paired_ratio", "ratio", "wilcoxon_p"]

#: The confidence level of every interval of a league table.
LEVEL = 0.95


def _worst_last(values: Sequence[float]) -> np.ndarray:
    """The values with nan (a failed run) as +inf: worst, and sortable."""
    x = np.asarray(values, dtype=np.float64)
    return np.where(np.isnan(x), np.inf, x)


@functools.lru_cache(maxsize=256)
def order_statistic_rank(n: int, level: float = LEVEL) -> int | None:
    """The largest l (1-based) such that ``[x[l], x[n+1-l]]`` covers the
    median with probability >= `level`; None when even [min, max] does not."""
    from scipy.stats import binom

    if n < 1:
        return None
    alpha = 1.0 - level
    # P(x[l] > median) = P(B <= l - 1); both tails together at most alpha.
    l = int(binom.ppf(alpha / 2.0, n, 0.5))
    # ppf gives the smallest k with cdf(k) >= alpha/2; the tail must stay below it.
    while l >= 1 and 2.0 * binom.cdf(l - 1, n, 0.5) > alpha:
        l -= 1
    while 2.0 * binom.cdf(l, n, 0.5) <= alpha:
        l += 1
    return l if l >= 1 else None


def median_ci(values: Sequence[float], level: float = LEVEL) -> tuple[float, float]:
    """The distribution-free `level` interval of the median (nan, nan when
    there are too few values for one)."""
    x = np.sort(_worst_last(values))
    l = order_statistic_rank(len(x), level)
    if l is None:
        return math.nan, math.nan
    return float(x[l - 1]), float(x[len(x) - l])


def ratio(x: float, y: float) -> float:
    """x / y where a failed run (inf or nan) counts as infinitely bad: a
    finite x against a failed y is 0, the reverse inf, two failures a tie."""
    fx, fy = math.isfinite(x), math.isfinite(y)
    if fx and fy:
        return x / y if y > 0 else (1.0 if x == 0 else math.inf)
    if fx:
        return 0.0
    return math.inf if fy else 1.0


def paired_ratio(values: Sequence[float], reference: Sequence[float],
                 level: float = LEVEL) -> tuple[float, float, float, int]:
    """Over paired plants: the median of value / reference, its interval,
    and the number of plants where the value is lower."""
    r = [ratio(float(a), float(b)) for a, b in zip(values, reference, strict=True)]
    low, high = median_ci(r, level)
    return float(np.median(r)) if r else math.nan, low, high, sum(x < 1.0 for x in r)


def wilcoxon_p(values: Sequence[float], reference: Sequence[float]) -> float:
    """The two-sided Wilcoxon signed-rank p-value of the paired differences
    (nan with fewer than two plants). A failed run is worse than any
    finished one: it is replaced by a value above every finite one, which
    keeps the signs and the ranks the test uses."""
    from scipy.stats import wilcoxon

    a, b = _worst_last(values), _worst_last(reference)
    if len(a) < 2:
        return math.nan
    finite = np.concatenate([a[np.isfinite(a)], b[np.isfinite(b)]])
    big = 2.0 * float(np.max(np.abs(finite))) + 1.0 if finite.size else 1.0
    d = np.where(np.isfinite(a), a, big) - np.where(np.isfinite(b), b, big)
    nonzero = d[d != 0.0]
    if nonzero.size == 0:
        return 1.0
    # The exact distribution needs no ties among |d|; with ties, the normal
    # approximation (SciPy would switch to it with a warning).
    ties = np.unique(np.abs(nonzero)).size < nonzero.size
    method = "approx" if ties or nonzero.size > 50 else "exact"
    return float(wilcoxon(nonzero, zero_method="wilcox", method=method).pvalue)


def holm(p_values: Sequence[float]) -> list[float]:
    """Holm's step-down adjustment of a family of p-values (nan stays nan and
    is not counted in the family). SciPy has Benjamini-Hochberg but not Holm."""
    p = np.asarray(p_values, dtype=np.float64)
    out = np.full(p.shape, math.nan)
    idx = np.flatnonzero(~np.isnan(p))
    m = idx.size
    running = 0.0
    for k, i in enumerate(idx[np.argsort(p[idx], kind="stable")]):
        running = max(running, min(1.0, (m - k) * p[i]))
        out[i] = running
    return out.tolist()


def paired_ranks(order: Sequence[str], samples: dict[str, dict[int, float]],
                 level: float = LEVEL) -> list[int] | None:
    """Ranks of the controllers in `order` (best median first) from paired
    comparisons: each is compared with the first of the rank above it on
    the plants both ran; it shares that rank while the interval of their
    paired ratio contains 1. None when a pair has too few plants for an
    interval (the caller ranks by the medians)."""
    if not order:
        return []
    ranks = [1]
    leader = order[0]
    for i, c in enumerate(order[1:], start=1):
        common = sorted(set(samples[c]) & set(samples[leader]))
        _, low, high, _ = paired_ratio([samples[c][k] for k in common], [samples[leader][k] for k in common], level)
        if math.isnan(low):
            return None
        if low <= 1.0 <= high:
            ranks.append(ranks[order.index(leader)])
        else:
            ranks.append(i + 1)
            leader = c
    return ranks
