"""Stage 2, output error: the vehicle model itself, integrated by neurov's
plant integrator (the RK4 step the simulator takes, every segment of an
evaluation in one ``neurov._core.rk4_segments`` call), fitted to the
measured velocities by ``scipy.optimize.least_squares`` over short segments (2 s by default; multiple shooting: each segment starts from the
measured state, so an error does not accumulate over the whole log),
started from stage 1, within physical bounds (added mass and damping >= 0,
mass and inertia > 0, buoyancy >= 0; with a diagonal M these keep M
symmetric positive definite).

On noise-free data the model that made the log has zero residual, so this
stage removes stage 1's discretisation bias (the midpoint rule's, of order
(omega dt)^2)."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray
from scipy.optimize import least_squares
from scipy.sparse import lil_matrix

from neurov import _core
from neurov.identification.blocks import Blocks, block_ids
from neurov.identification.errors import IdentificationError
from neurov.identification.guards import inseparable
from neurov.identification.estimator_model import ANGULAR, LINEAR, held_moves, refresh_rows, through_updates
from neurov.identification.log import Log
from neurov.identification.parameters import vehicle_parameters
from neurov.identification.survey import STILL

__all__ = ["Segment", "SegmentInputs", "ShootingFit", "bounds", "fit_output_error", "simulate_segments"]

Array = NDArray[np.float64]

# The solver's evaluations. Measured on the perturbed BlueROV2's 120 s
# realistic run (seed 0), 20 evaluations with the estimator modelled left
# 7 of 18 intervals holding the truth, 60 gave 15 of 18.
MAX_NFEV = 20
MAX_NFEV_ESTIMATOR = 60
# The estimator gains' start: a DVL update that trusts the sample more than
# the prediction (u, v, w), a gyro update that trusts it almost wholly (p, q, r).
GAIN0 = (0.8,) * 3 + (0.95,) * 3


# The residual of a trial point whose simulation overflowed.
OVERFLOW = 1e6


def bounds(fitted: list[int], template: dict[str, Any]) -> tuple[Array, Array]:
    """Physical bounds of the fitted entries of theta."""
    lo = np.full(len(fitted), -np.inf)
    hi = np.full(len(fitted), np.inf)
    for j, i in enumerate(fitted):
        if i <= 3:
            lo[j] = 1e-9  # mass and inertia
        elif i <= 21:
            lo[j] = 0.0  # added mass, damping
        elif i == 22:
            hi[j] = float(template["weight"])  # W - B <= W: buoyancy >= 0
    return lo, hi


@dataclass(frozen=True)
class Segment:
    """Rows start .. start + steps of one log, simulated from row start."""

    log: Log
    start: int
    steps: int


def _segments(logs: list[Log], segment_s: float) -> list[Segment]:
    out = []
    for log in logs:
        steps = max(1, int(round(segment_s / log.dt)))
        for a, b in log.segments:
            for s in range(a, b - 1, steps):
                n = min(steps, b - 1 - s)
                if n >= 1:
                    out.append(Segment(log, s, n))
    return out


@dataclass(frozen=True)
class SegmentInputs:
    """What the segments' runs are driven by, packed in segment order as
    ``neurov._core.rk4_segments`` takes it: each segment's start pose, its
    intervals' steps, forces and currents (the same every evaluation of a
    fit, so packed once)."""

    eta0: Array
    steps: NDArray[np.int64]
    tau: Array
    dt: Array
    current: Array

    @staticmethod
    def of(segs: list[Segment]) -> SegmentInputs:
        def rows(x: Any, s: Segment) -> Any:
            return x[s.start:s.start + s.steps]

        return SegmentInputs(eta0=np.array([s.log.eta[s.start] for s in segs]).reshape(-1, 6),
                             steps=np.array([s.steps for s in segs], dtype=np.int64),
                             tau=np.concatenate([rows(s.log.tau, s) for s in segs]).reshape(-1, 6),
                             dt=np.concatenate([np.diff(s.log.t[s.start:s.start + s.steps + 1])
                                                for s in segs]),
                             current=np.concatenate([rows(s.log.current, s) for s in segs]).reshape(-1, 3))


def simulate_segments(vehicle: Any, segs: list[Segment], starts: Array, substeps: int,
                      inputs: SegmentInputs | None = None) -> Array:
    """The body velocities of every segment at its rows 0..steps, each
    started from its measured pose and its row of `starts` (len(segs), 6),
    driven by the log's force (and current) held over each interval,
    stacked in segment order: one call of ``neurov._core.rk4_segments``
    (the simulator's RK4 step, every segment in C++; `inputs`, packed once
    by :meth:`SegmentInputs.of`, saves packing them again)."""
    packed = SegmentInputs.of(segs) if inputs is None else inputs
    nu0 = np.asarray(starts, dtype=np.float64).reshape(-1, 6)
    return np.asarray(_core.rk4_segments(vehicle, packed.eta0, nu0, packed.steps, packed.tau, packed.dt,
                                         packed.current, substeps))


@dataclass
class ShootingFit:
    """The estimate (24,), and the blocks of the Gauss-Newton step taken
    from `at` (the solver's point, where the Jacobian is)."""

    theta: Array
    at: Array
    blocks: Blocks
    cost: float
    nfev: int
    rms: float = 0.0  #: RMS of the scaled residual at the solution (comparable across logs)
    rejected: int = 0  #: trial points whose simulation overflowed (given a large residual: rejected)
    gain: Array | None = None  #: the estimator's fitted update gains (u, v, w, p, q, r), with `estimator`
    dead: tuple[str, ...] = ()  #: the body velocities that never move in the logs: left out of the residual


def _profiled_blocks(jac: Any, fun: Array, p: int, segs: list[Segment], seg_blocks: Any,
                     keep: int | None = None) -> Blocks:
    """Per-block normal equations of theta with each segment's initial
    velocity eliminated (its Schur complement): resampling a block takes its
    segments' starts with it."""
    jac = jac.tocsr() if hasattr(jac, "tocsr") else jac
    n_blocks = int(seg_blocks.max()) + 1
    gram = np.zeros((n_blocks, p, p))
    rhs = np.zeros((n_blocks, p))
    row = 0
    for k, seg in enumerate(segs):
        rows = slice(row, row + 6 * (seg.steps + 1))
        row = rows.stop
        j = jac[rows]
        j = j.toarray() if hasattr(j, "toarray") else np.asarray(j)
        jt, jn, r = j[:, :p], j[:, p + 6 * k:p + 6 * k + 6], fun[rows]
        nn = jn.T @ jn
        proj = jt.T @ jn @ np.linalg.pinv(nn)
        b = seg_blocks[k]
        gram[b] += jt.T @ jt - proj @ jn.T @ jt
        rhs[b] -= jt.T @ r - proj @ (jn.T @ r)
    return Blocks(gram, rhs, keep)


def fit_output_error(logs: list[Log], template: dict[str, Any], theta0: Array, fitted: list[int],
                     segment_s: float = 2.0, substeps: int = 1, block_s: float = 5.0,
                     max_nfev: int | None = None, estimator: bool = False,
                     rates: bool = True) -> ShootingFit:
    """Fits theta[fitted] from `theta0` by multiple shooting on segments
    of `segment_s` seconds (measured on the 60 s NEROV runs of
    examples/identify_coverage.py, 2 s has errors a half to a third of
    0.5 s's), each integrated with `substeps` RK4 steps
    per interval. Each segment's initial velocity is fitted too (starting
    from the measured one, itself a measurement in the residual): a noisy
    start would otherwise bias the damping (an error in the variables).
    With `estimator`, the model's velocities go through the log's
    estimator updates (:mod:`neurov.identification.estimator_model`: the
    linear ones on their update rows, the rates on theirs), their gains
    (u, v, w, p, q, r) fitted as nuisance unknowns after theta; without
    `rates`, the linear ones only (a log of raw gyro rates). `max_nfev` bounds
    the solver's evaluations (default MAX_NFEV, or MAX_NFEV_ESTIMATOR with
    the estimator, whose start from stage 1 is further off)."""
    if segment_s <= 0:
        raise IdentificationError(f"segment_s: expected seconds > 0, got {segment_s}")
    segs = _segments(logs, segment_s)
    if not segs:
        raise IdentificationError("no interval to fit the output error on")
    measured = np.concatenate([s.log.nu[s.start:s.start + 1 + s.steps] for s in segs])
    rms = np.sqrt(np.mean(measured**2, axis=0))
    # A velocity that never moves (the log report's rule: a dead signal, as
    # rates never filled in) measures nothing: left out of the residual.
    # Scaled by its own RMS (~1e-7) it would outweigh any real misfit and even
    # OVERFLOW, and the solver would walk into overflowing points.
    moving = np.ptp(measured, axis=0) > np.asarray(STILL[6:12])
    weight = np.where(moving, 1.0 / np.where(rms > 0, rms, 1.0), 0.0)
    scale = np.where(rms > 0, rms, 1.0)
    p = len(fitted)
    rates = rates and bool(moving[3:].all())  # a dead rate cannot tell its filter's gain
    extra = (6 if rates else 3) if estimator else 0

    def seg_rows(axes: slice) -> tuple[NDArray[np.bool_], Array]:
        fresh = [refresh_rows(log, axes) for log in logs]
        moves = [held_moves(log, f, axes) for log, f in zip(logs, fresh)]

        def cut(x: list[Any]) -> Any:
            return np.concatenate([x[logs.index(s.log)][s.start:s.start + 1 + s.steps] for s in segs])

        return cut(fresh), cut(moves)

    (fresh_lin, moves_lin), (fresh_rot, moves_rot) = seg_rows(LINEAR), seg_rows(ANGULAR)
    seg_e0 = np.array([s.log.nu[s.start] for s in segs])
    lengths = np.array([s.steps + 1 for s in segs], dtype=np.int64)
    inputs = SegmentInputs.of(segs)
    # Blocks of whole segments, about block_s seconds each.
    seg_t = np.array([s.log.t[s.start] for s in segs])
    log_no = np.array([logs.index(s.log) for s in segs])
    seg_blocks = block_ids(log_no, seg_t, block_s)

    rejected, calls = [0], [0]

    def residual(x: Array) -> Array:
        theta = theta0.copy()
        theta[fitted] = x[:p]
        vehicle = _core.Vehicle(**vehicle_parameters(template, theta))
        starts = x[p + extra:].reshape(-1, 6)
        try:
            pred = simulate_segments(vehicle, segs, starts, substeps, inputs)
        except ValueError:
            # An overflowing trial point: a residual far above any finite
            # one makes the solver reject the step; counted and said.
            rejected[0] += 1
            if calls[0] == 0:  # the start itself: the stage cannot begin
                raise
            return np.full(measured.size, OVERFLOW)
        calls[0] += 1
        if estimator:
            pred[:, LINEAR] = through_updates(pred[:, LINEAR], lengths, fresh_lin, x[p:p + 3],
                                              seg_e0[:, LINEAR], moves_lin)
            if rates:
                pred[:, ANGULAR] = through_updates(pred[:, ANGULAR], lengths, fresh_rot, x[p + 3:p + 6],
                                                   seg_e0[:, ANGULAR], moves_rot)
        return ((pred - measured) * weight).reshape(-1)

    lo_t, hi_t = bounds(fitted, template)
    x0_t = np.clip(theta0[fitted], lo_t, hi_t)
    # The lower bound itself can be the answer (a zero damping): start just inside.
    x0_t = np.where(x0_t <= lo_t, np.where(np.isfinite(lo_t), lo_t + 1e-6 * np.maximum(1, np.abs(x0_t)),
                                           x0_t), x0_t)
    starts0 = np.concatenate([s.log.nu[s.start] for s in segs])
    gain0 = np.array(GAIN0[:extra], dtype=np.float64)
    x0 = np.concatenate([x0_t, gain0, starts0])
    lo = np.concatenate([lo_t, np.full(extra, 1e-3), np.full(starts0.size, -np.inf)])
    hi = np.concatenate([hi_t, np.ones(extra), np.full(starts0.size, np.inf)])
    typical = np.concatenate([np.maximum(np.abs(x0_t), 1e-3 * np.max(np.abs(x0_t))), np.ones(extra),
                              np.tile(scale, len(segs))])
    sparsity = lil_matrix((measured.size, x0.size), dtype=np.int8)
    row = 0
    for k, seg in enumerate(segs):
        n = 6 * (seg.steps + 1)
        sparsity[row:row + n, :p + extra] = 1
        sparsity[row:row + n, p + extra + 6 * k:p + extra + 6 * k + 6] = 1
        row += n
    sol = least_squares(residual, x0, bounds=(lo, hi), x_scale=typical, method="trf",
                        tr_solver="lsmr", jac_sparsity=sparsity, xtol=1e-10, ftol=1e-10,
                        gtol=1e-10,
                        max_nfev=max_nfev or (MAX_NFEV_ESTIMATOR if estimator else MAX_NFEV))
    # One Gauss-Newton step per resampled set of blocks from the solution
    # (the bootstrap); with every block once it finishes the fit where the
    # bounded solver stopped short of a bound.
    fun = np.asarray(sol.fun)
    if np.all(fun == OVERFLOW):
        raise IdentificationError("every simulation from the solver's points overflowed")
    blocks = _profiled_blocks(sol.jac, fun, p + extra, segs, seg_blocks, keep=p)
    try:
        step = blocks.solve()
    except np.linalg.LinAlgError:  # named, as numpy's bare "Singular matrix" says nothing
        raise IdentificationError("its normal equations are singular at the solution: "
                                  + inseparable(blocks.gram.sum(axis=0)[:p, :p], fitted)) from None
    theta = theta0.copy()
    theta[fitted] = np.clip(sol.x[:p] + step, lo_t, hi_t)
    at = theta0.copy()
    at[fitted] = sol.x[:p]
    return ShootingFit(theta, at, blocks, float(sol.cost), int(sol.nfev),
                       float(np.sqrt(np.mean(fun**2))), gain=sol.x[p:p + extra].copy() if extra else None,
                       rejected=rejected[0], dead=tuple(n for n, m in zip("uvwpqr", moving) if not m))
