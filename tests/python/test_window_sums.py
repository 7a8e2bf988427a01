"""The metrics' window sums are made once, in C++ (sim/window_sums.hpp), for a
C++ run and for a Python Result's rows alike: _core.RunSums gives the sums
numpy gives of the same rows to 1e-12 relative, in one piece or in chunks."""

from __future__ import annotations

import math
from pathlib import Path
from types import SimpleNamespace

import neurov
import numpy as np
import pytest
from neurov import _core
from neurov.config.scenario import ControllerSpec
from neurov.results.metrics import MetricsWindow, WindowSums
from neurov.running.simulation import simulate

SCENARIOS = Path(neurov.__file__).parent / "scenarios"
COLUMNS = ("t", "eta", "eta_d", "tau_demanded", "controller_status", "adaptive_norm")


def numpy_sums(t: np.ndarray, e: np.ndarray, tau: np.ndarray, status: np.ndarray) -> dict:
    """The sums of some rows written out in numpy: the reference the C++ is held to."""
    with np.errstate(over="ignore", invalid="ignore"):  # a diverged run's rows
        pos, ae, at = np.linalg.norm(e[:, :3], axis=1), np.abs(e), np.abs(tau)
        return {"rows": len(t), "t_first": t[0], "t_last": t[-1], "e2": np.sum(e**2, axis=0),
                "abs_e": np.sum(ae, axis=0), "max_abs_e": np.max(ae, axis=0), "pos2": np.sum(pos**2),
                "max_pos": np.max(pos), "abs_tau": np.sum(at), "abs_tau_dof": np.sum(at, axis=0),
                "max_abs_tau_dof": np.max(at, axis=0), "tau_norm": np.sum(np.linalg.norm(tau, axis=1)),
                "refused": int(np.count_nonzero(status))}


def close(a: object, b: object) -> bool:
    a, b = np.atleast_1d(np.asarray(a, float)), np.atleast_1d(np.asarray(b, float))
    with np.errstate(invalid="ignore"):  # inf - inf
        near = np.abs(a - b) <= 1e-12 * np.maximum(np.abs(a), np.abs(b))
    return bool(np.all((a == b) | (np.isnan(a) & np.isnan(b)) | near))


def runs() -> list[neurov.Result]:
    plain = neurov.load_scenario(SCENARIOS / "paper_fig3.toml").replace()
    plain.duration = 30.0
    wild = plain.replace()
    wild.simulation.dt, wild.simulation.substeps = 2.0, 1  # diverges at t = 8 s
    return [simulate(plain), simulate(wild, ControllerSpec("pd", kp=[1e7] * 6, kd=[1e7] * 6))]


@pytest.mark.parametrize("after", [12.0, 0.0])
def test_the_sums_of_a_results_rows_are_numpys_in_one_piece_or_in_chunks(after: float) -> None:
    for r in runs():
        e = r.eta - r.eta_d
        window = r.t >= after
        expected = {part: numpy_sums(r.t[rows], e[rows], r.tau_demanded[rows], r.controller_status[rows])
                    for part, rows in (("window", window), ("before", ~window)) if rows.any()}
        whole = _core.RunSums(after)
        whole.add(*(getattr(r, name) for name in COLUMNS), r.diverged)
        chunked = _core.RunSums(after)
        for k in range(0, len(r.t), 7):
            chunked.add(*(getattr(r, name)[k:k + 7] for name in COLUMNS), r.diverged)
        for got in (whole.as_dict(), chunked.as_dict()):
            for part, sums in expected.items():
                for name, value in sums.items():
                    assert close(got[part][name], value), (part, name, got[part][name], value)
            assert got["diverged"] == r.diverged
            assert got["final_adaptive_norm"] == r.adaptive_norm[-1]
            assert close(got["max_adaptive_norm"], np.max(r.adaptive_norm))
        fed = MetricsWindow(r.scenario.duration, r.scenario.dt, after)
        for k in range(0, len(r.t), 7):  # as neurov run streams a run, in chunks of rows
            fed.add(SimpleNamespace(diverged=r.diverged, **{name: getattr(r, name)[k:k + 7] for name in COLUMNS}))
        assert fed.value() == MetricsWindow.from_sums(whole.as_dict(), r.scenario.duration, r.scenario.dt).value()


def test_a_python_window_sums_holds_the_cpp_ones() -> None:
    empty = WindowSums()
    assert empty.rows == 0 and math.isnan(empty.t_first) and np.all(empty.max_abs_e == -np.inf)
    names = [name for name, _, _ in _core.WINDOW_SUMS]
    assert list(vars(empty)) == names and list(WindowSums.__annotations__) == names


def test_rows_of_different_lengths_are_named() -> None:
    sums = _core.RunSums(0.0)
    with pytest.raises(ValueError, match="'eta_d' must have 3 rows"):
        sums.add(np.zeros(3), np.zeros((3, 6)), np.zeros((2, 6)), np.zeros((3, 6)), np.zeros(3, np.uint8),
                 np.zeros(3), False)
