"""Stage 1, equation error: least squares on the regressor Y theta = tau.

Each interval [t_k, t_k+1) of a log gives one equation (six rows): its mean
acceleration (nu_k+1 - nu_k) / dt_k, the exact mean of nu_dot over the
interval, and the midpoint's velocity and attitude in the regressor
(``neurov._core.regressor``, the same Y the adaptive controller uses); the
force is the interval's (the zero-order hold). Both sides are then smoothed
by the same Savitzky-Golay filter (``scipy.signal.savgol_filter``) along
each segment: the filtered mean acceleration is a smoothing differentiator
of nu, and since the filter is linear and theta constant the filtered
equation holds wherever the raw one does, while the noise is lowered."""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
from numpy.typing import NDArray
from scipy.signal import savgol_filter

from neurov import _core
from neurov.identification.blocks import Blocks, block_ids
from neurov.identification.errors import IdentificationError
from neurov.identification.log import Log

__all__ = ["EquationRows", "LinearFit", "equation_rows", "fit_linear", "identifiable"]

Array = NDArray[np.float64]

# A scaled information matrix worse than this is rank-deficient in practice:
# its weakest direction is a combination the data cannot tell apart.
CONDITION_LIMIT = 1e4
# A column this much weaker than the strongest is a parameter never excited.
UNEXCITED = 1e-9


@dataclass(frozen=True)
class EquationRows:
    """The equations of one or more logs: Y (M, 6, 24), tau (M, 6), the
    interval's time, segment and block."""

    y: Array
    tau: Array
    t: Array
    segment: NDArray[np.int64]
    block: NDArray[np.int64]


def _wrap(a: Array) -> Array:
    return (a + np.pi) % (2 * np.pi) - np.pi


def _window(dt: float, window_s: float, polyorder: int) -> int:
    w = max(int(round(window_s / dt)), polyorder + 2)
    return w + 1 if w % 2 == 0 else w


def equation_rows(logs: list[Log], window_s: float = 0.5, polyorder: int = 3,
                  block_s: float = 5.0) -> EquationRows:
    """The filtered interval equations of `logs`; segments shorter than the
    filter's window are left out."""
    ys, taus, ts, segs = [], [], [], []
    seg_no = 0
    for log in logs:
        w = _window(log.dt, window_s, polyorder)
        for a, b in log.segments:
            if b - a - 1 < w:
                continue
            t, eta, nu = log.t[a:b], log.eta[a:b], log.nu[a:b]
            dt = np.diff(t)
            acc = np.diff(nu, axis=0) / dt[:, None]
            nu_m = 0.5 * (nu[1:] + nu[:-1])
            eta_m = eta[:-1] + 0.5 * np.concatenate(
                [np.diff(eta[:, :3], axis=0), _wrap(np.diff(eta[:, 3:], axis=0))], axis=1)
            c_m = 0.5 * (log.current[a:b][1:] + log.current[a:b][:-1])
            y = np.empty((len(dt), 6, 24))
            for k in range(len(dt)):
                nu_r = nu_m[k].copy()
                if c_m[k].any():
                    nu_r[:3] -= _core.rotation(*eta_m[k, 3:]).T @ c_m[k]
                y[k] = _core.regressor(acc[k], nu_r, nu_m[k], eta_m[k])
            ys.append(savgol_filter(y, w, polyorder, axis=0))
            taus.append(savgol_filter(log.tau[a:b - 1], w, polyorder, axis=0))
            ts.append(0.5 * (t[1:] + t[:-1]))
            segs.append(np.full(len(dt), seg_no, dtype=np.int64))
            seg_no += 1
    if not ys:
        raise IdentificationError(
            "the logs have no segment longer than the differentiator's window "
            f"({window_s} s): too short")
    t_all, seg_all = np.concatenate(ts), np.concatenate(segs)
    return EquationRows(np.concatenate(ys), np.concatenate(taus), t_all, seg_all,
                        block_ids(seg_all, t_all, block_s))


def dof_scale(tau: Array) -> Array:
    """Per-DOF row weights: 1 / the RMS force of that DOF (N and N m made
    comparable); a DOF that felt no force gets weight 1."""
    rms = np.sqrt(np.mean(tau**2, axis=0))
    return np.where(rms > 0, 1.0 / np.where(rms > 0, rms, 1.0), 1.0)


def identifiable(a: Array, free: list[int]) -> tuple[list[int], dict[int, str], float]:
    """Splits `free` (columns of `a`) into the identifiable ones and the
    rest with a reason, from the column-scaled information matrix: a column
    that is (nearly) zero was never excited; while the matrix's condition
    number exceeds CONDITION_LIMIT, the parameter that weighs most in its
    weakest direction is set aside (it moves together with others).
    Returns (identifiable, reasons, condition number of what is kept)."""
    norms = np.linalg.norm(a, axis=0)
    top = norms.max() if norms.size and norms.max() > 0 else 1.0
    reasons: dict[int, str] = {}
    keep = []
    for j, i in enumerate(free):
        if norms[j] <= UNEXCITED * top:
            reasons[i] = "not excited: the DOF it acts in never moved (or felt no force) in the logs"
        else:
            keep.append(j)
    # The small scaled Gram matrix's eigenvalues are the squared singular
    # values (the limit's square, 1e8, is far from double precision's reach).
    gram = (a.T @ a) / np.outer(np.where(norms > 0, norms, 1.0), np.where(norms > 0, norms, 1.0))
    while keep:
        lam, vec = np.linalg.eigh(gram[np.ix_(keep, keep)])
        cond = float(np.sqrt(lam[-1] / lam[0])) if lam[0] > 0 else float("inf")
        if cond <= CONDITION_LIMIT:
            return [free[j] for j in keep], reasons, cond
        weak = vec[:, 0]
        worst = int(np.argmax(np.abs(weak)))
        partners = [_core.THETA_NAMES[free[keep[j]]] for j in np.argsort(-np.abs(weak))[1:3]
                    if abs(weak[j]) > 0.1]
        with_ = f" (moves with {', '.join(partners)})" if partners else ""
        reasons[free[keep[worst]]] = (f"not separable: the information matrix's condition number is "
                                      f"{cond:.3g}{with_}")
        del keep[worst]
    return [], reasons, float("inf")


@dataclass
class LinearFit:
    """Stage 1's estimate: theta (24,) with the template's values where not
    fitted, the fitted indices, the ones set aside and why, the condition
    number, and the blocks for the bootstrap."""

    theta: Array
    fitted: list[int]
    reasons: dict[int, str]
    condition: float
    blocks: Blocks
    rows: EquationRows
    residual_rms: Array = field(default_factory=lambda: np.zeros(6))


def fit_linear(rows: EquationRows, theta0: Array, free: list[int]) -> LinearFit:
    """Weighted least squares for the identifiable ones of `free`, the
    others held at `theta0`."""
    w = dof_scale(rows.tau)
    fixed = [i for i in range(24) if i not in free]
    b = (rows.tau - rows.y[:, :, fixed] @ theta0[fixed]) * w
    a_full = rows.y[:, :, free] * w[None, :, None]
    a = a_full.reshape(-1, len(free))
    fitted, reasons, cond = identifiable(a, free)
    if not fitted:
        raise IdentificationError("none of the free parameters can be identified from the logs: "
                                  + "; ".join(f"{_core.THETA_NAMES[i]}: {r}" for i, r in reasons.items()))
    cols = [free.index(i) for i in fitted]
    held = [i for i in free if i not in fitted]
    b = b - (rows.y[:, :, held] @ theta0[held]) * w if held else b
    ids = np.repeat(rows.block, 6)
    blocks = Blocks.from_rows(a[:, cols], b.reshape(-1), ids)
    theta = theta0.copy()
    theta[fitted] = blocks.solve()
    resid = rows.tau - rows.y @ theta
    return LinearFit(theta, fitted, reasons, cond, blocks, rows,
                     np.sqrt(np.mean(resid**2, axis=0)))
