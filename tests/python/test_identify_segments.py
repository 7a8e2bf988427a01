"""The output error's segment runs in C++ (``neurov._core.rk4_segments``
through ``simulate_segments``) against the Python loop of ``rk4_step`` they
replaced, kept here as the reference; the estimator's updates over all
segments at once (with another sensor's moves between them) against the
one-segment loop; and bad input named."""

from __future__ import annotations

import numpy as np
import pytest
from identify_runs import excitation_run

import neurov
from neurov import _core
from neurov.identification import make_log
from neurov.identification.estimator_model import refresh_rows, through_updates
from neurov.identification.heldout import free_run
from neurov.identification.output_error import Segment, _segments, simulate_segments


def _python_reference(vehicle, segs, starts, substeps):
    """simulate_segments as it was: rk4_step called from Python per step."""
    out = []
    for seg, nu0 in zip(segs, starts):
        log = seg.log
        eta = log.eta[seg.start].copy()
        nu = np.array(nu0, dtype=np.float64)
        path = np.empty((seg.steps + 1, 6))
        path[0] = nu
        for j in range(seg.steps):
            k = seg.start + j
            h = (log.t[k + 1] - log.t[k]) / substeps
            for _ in range(substeps):
                eta, nu = _core.rk4_step(vehicle, eta, nu, log.tau[k], h, log.current[k])
            path[j + 1] = nu
        out.append(path)
    return np.concatenate(out)


def _log_with_uneven_time_and_a_current():
    r = excitation_run("nerov", 20.0, noise=0.01)
    rng = np.random.default_rng(3)
    t = r.t + rng.uniform(-0.01, 0.01, len(r.t)) * (np.arange(len(r.t)) > 0)
    current = np.column_stack([0.2 * np.sin(0.3 * r.t), 0.1 * np.cos(0.2 * r.t), 0.02 * np.ones_like(r.t)])
    return make_log("uneven", t, r.eta_estimate, r.nu_estimate, r.tau_applied + r.disturbance, current)


@pytest.mark.parametrize("substeps", [1, 3])
def test_segments_in_cpp_equal_the_python_loop(substeps: int) -> None:
    log = _log_with_uneven_time_and_a_current()
    vehicle = neurov.Vehicle.preset("nerov")
    segs = _segments([log], 1.7)
    assert len(segs) > 5 and len({s.steps for s in segs}) > 1  # a short last segment too
    starts = np.array([log.nu[s.start] for s in segs]) + 0.01
    fast = simulate_segments(vehicle, segs, starts, substeps)
    slow = _python_reference(vehicle, segs, starts, substeps)
    assert fast.shape == slow.shape == (sum(s.steps + 1 for s in segs), 6)
    np.testing.assert_allclose(fast, slow, rtol=1e-12, atol=1e-12 * np.max(np.abs(slow)))


def test_the_held_out_free_run_equals_the_python_loop() -> None:
    log = _log_with_uneven_time_and_a_current()
    vehicle = neurov.Vehicle.preset("nerov")
    segs = [Segment(log, a, b - 1 - a) for a, b in log.segments]
    slow = _python_reference(vehicle, segs, np.array([log.nu[a] for a, _ in log.segments]), 1)
    np.testing.assert_allclose(free_run(vehicle, log), slow, rtol=1e-12, atol=1e-12 * np.max(np.abs(slow)))


def test_the_estimator_s_updates_over_all_segments_equal_the_one_segment_loop() -> None:
    log = _log_with_uneven_time_and_a_current()
    fresh = np.arange(len(log.t)) % 4 == 0  # a sensor update every 4th row
    assert refresh_rows(log).mean() > 0.95  # (this log's own velocity moves at nearly every row)
    segs = _segments([log], 1.7)
    rng = np.random.default_rng(5)
    pred = rng.normal(size=(sum(s.steps + 1 for s in segs), 3))
    seg_fresh = np.concatenate([fresh[s.start:s.start + s.steps + 1] for s in segs])
    e0 = rng.normal(size=(len(segs), 3))
    gain = np.array([0.85, 0.8, 0.9])
    lengths = np.array([s.steps + 1 for s in segs])
    # Another sensor's moves between the updates (on the updates and at a segment's start, ignored).
    moves = rng.normal(scale=0.01, size=pred.shape)
    for with_moves in (False, True):
        got = through_updates(pred, lengths, seg_fresh, gain, e0, moves if with_moves else None)
        row = 0
        for i, n in enumerate(lengths):
            e = e0[i].copy()
            want = np.empty((n, 3))
            want[0] = e
            for j in range(1, n):
                if seg_fresh[row + j]:
                    e = e + gain * (pred[row + j] - e)
                elif with_moves:
                    e = e + moves[row + j]
                want[j] = e
            np.testing.assert_allclose(got[row:row + n], want, rtol=0, atol=1e-14)
            row += n


def test_bad_segment_input_is_named() -> None:
    v = neurov.Vehicle.preset("nerov")
    z6, z1 = np.zeros((1, 6)), np.zeros((3, 6))
    with pytest.raises(ValueError, match="argument 'tau' must have shape \\(2, 6\\)"):
        _core.rk4_segments(v, z6, z6, [2], z1, [0.05, 0.05])
    with pytest.raises(ValueError, match="argument 'steps' must be >= 0; element 0 is -1"):
        _core.rk4_segments(v, z6, z6, [-1], np.zeros((0, 6)), np.zeros(0))
    with pytest.raises(TypeError, match="argument 'steps' must be a 1-d integer array"):
        _core.rk4_segments(v, z6, z6, [1.5], np.zeros((1, 6)), [0.05])
    with pytest.raises(ValueError, match="argument 'dt' divided by substeps must be > 0 .* element 1 is 0"):
        _core.rk4_segments(v, z6, z6, [2], np.zeros((2, 6)), [0.05, 0.0])
    with pytest.raises(ValueError, match="argument 'nu0' must be finite"):
        _core.rk4_segments(v, z6, np.full((1, 6), np.nan), [1], np.zeros((1, 6)), [0.05])
    with pytest.raises(ValueError, match="substeps must be >= 1, got 0"):
        _core.rk4_segments(v, z6, z6, [1], np.zeros((1, 6)), [0.05], substeps=0)
    # A step that fails raises as rk4_step does, naming where.
    huge = np.array([[0.0] * 6, [1e200] * 6])
    with pytest.raises(ValueError) as python_error:
        _core.rk4_step(v, huge[1], huge[1], np.zeros(6), 0.05)
    message = str(python_error.value).split(": ", 1)[1]
    with pytest.raises(ValueError, match="rk4_segments: segment 1, step 0") as cpp_error:
        _core.rk4_segments(v, np.zeros((2, 6)), huge, [1, 1], np.zeros((2, 6)), [0.05, 0.05])
    assert str(cpp_error.value).endswith(message)
