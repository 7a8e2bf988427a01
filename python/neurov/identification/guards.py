"""What a fit must say about itself: too short, too quiet, intervals of zero
width or pinned at a bound, parameters the data cannot separate (named as
combinations), estimates far from the template, and the verdict of a free
run of the fitted vehicle (held-out logs, or the fitted logs themselves)."""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import NDArray

from neurov import _core
from neurov.identification.log import Log
from neurov.identification.parameters import GROUPS

__all__ = ["FIT_VERDICT", "MIN_BLOCKS", "WIDE", "fit_warnings", "inseparable", "verdict_warnings"]

Array = NDArray[np.float64]
_BODY = ("u", "v", "w", "p", "q", "r")

# Fewer blocks than this give a rough bootstrap.
MIN_BLOCKS = 10
# A 95 % interval wider than this fraction of the estimate either side: too quiet.
WIDE = 0.5
# A free run's NRMSE fit below this (%) in a DOF that moved: the template's
# structure or the log is wrong (ours: the excitation runs of
# docs/identification.md fit above 80 % in every DOF).
FIT_VERDICT = 50.0
# An estimate more than this factor from a non-zero template value is said.
FAR = 3.0


def _group(i: int) -> tuple[int, ...]:
    return next(g for g in GROUPS.values() if i in g)


def inseparable(gram: Array, fitted: list[int], weight: float = 0.3) -> str:
    """The parameter combinations the normal matrix `gram` (of `fitted`,
    any scaling) cannot separate: its weakest eigenvectors, in words."""
    g = np.asarray(gram, dtype=np.float64)
    d = np.sqrt(np.clip(np.diag(g), 1e-300, None))
    s = g / np.outer(d, d)
    w, v = np.linalg.eigh(s)
    parts = []
    for k in np.flatnonzero(w < max(1e-8, 1e-8 * w[-1]))[:3] if w[-1] > 0 else []:
        vec = v[:, k] / np.max(np.abs(v[:, k]))
        names = [f"{vec[j]:+.2f} {_core.THETA_NAMES[fitted[j]]}" for j in np.flatnonzero(np.abs(vec) > weight)]
        parts.append(" ".join(names))
    if not parts:
        k = int(np.argmin(w))
        vec = v[:, k] / np.max(np.abs(v[:, k]))
        parts.append(" ".join(f"{vec[j]:+.2f} {_core.THETA_NAMES[fitted[j]]}"
                              for j in np.flatnonzero(np.abs(vec) > weight)))
    return "the data cannot separate " + "; ".join(f"({p})" for p in parts)


def fit_warnings(logs: list[Log], rows: Any, fit: Any, interval: Array, theta: Array,
                 theta0: Array, lo: Array, hi: Array) -> list[str]:
    out = []
    for log in logs:
        out += [f"{log.source}: {n}" for n in (*log.problems, *log.notes)]
    if fit.blocks.count < MIN_BLOCKS:
        out.append(f"too short: {fit.blocks.count} blocks of data (fewer than {MIN_BLOCKS}); the "
                   "95 % intervals from so few are rough: record longer")
    y = rows.y
    for d in range(6):
        lin, quad = 10 + d, 16 + d
        if lin in fit.fitted and quad in fit.fitted:
            a, b = y[:, d, lin], y[:, d, quad]
            if np.std(a) > 0 and np.std(b) > 0 and abs(np.corrcoef(a, b)[0, 1]) > 0.99:
                out.append(f"too slow in {_BODY[d]}: the speed stays in too narrow a range to tell "
                           f"linear from quadratic damping apart (correlation "
                           f"{np.corrcoef(a, b)[0, 1]:.3f}); excite it with larger amplitudes")
    for k, i in enumerate(fit.fitted):
        name = _core.THETA_NAMES[i]
        ilo, ihi = interval[i]
        half = 0.5 * (ihi - ilo)
        scale = max(abs(theta[i]), max(abs(theta[j]) for j in _group(i)) * 1e-2)
        if not ihi > ilo:
            out.append(f"zero-width interval for {name}: [{ilo:.4g}, {ihi:.4g}] says nothing about its "
                       "uncertainty (every resample gave the same value, often a bound): do not trust it")
        elif half > WIDE * scale:
            out.append(f"too quiet for {name}: its 95 % interval [{ilo:.4g}, {ihi:.4g}] "
                       f"is wide for the estimate {theta[i]:.4g}; excite its DOF harder or longer")
        bound = _at_bound(theta[i], lo[k], hi[k])
        if bound is not None and _at_bound(theta0[i], lo[k], hi[k]) is None:
            out.append(f"{name} is pinned at its bound {bound:.4g}: the data push it outside the physical "
                       "range (a wrong template structure, or a DOF the log does not excite)")
        if theta0[i] != 0 and not 1 / FAR <= abs(theta[i] / theta0[i]) <= FAR:
            out.append(f"{name} moved from the template's {theta0[i]:.4g} to {theta[i]:.4g} (more than "
                       f"{FAR:g}x): check the template's structure (a term missing elsewhere ends up here)")
    return out


def _at_bound(x: float, lo: float, hi: float) -> float | None:
    for b in (lo, hi):
        if np.isfinite(b) and abs(x - b) <= 1e-9 * max(1.0, abs(b)):
            return float(b)
    return None


def verdict_warnings(source: str, fit: Array, moved: Array, what: str) -> list[str]:
    """A warning where the free run's fit % is below FIT_VERDICT in a DOF
    that moved (`moved`: bool per DOF)."""
    bad = [f"{_BODY[d]} {fit[d]:.1f} %" for d in range(6) if moved[d] and np.isfinite(fit[d])
           and fit[d] < FIT_VERDICT]
    if not bad:
        return []
    return [f"{what} on {source}: {', '.join(bad)} (below {FIT_VERDICT:g} %): the fitted vehicle does not "
            "reproduce the motion; the template's structure (a term fixed at a wrong value, a missing "
            "term) or the log (forces, units, timing) is wrong"]
