"""A streamed run (``neurov run``): the rows handed over in chunks give the
same files, metrics and drawn rows as the whole run held in memory."""

from __future__ import annotations

import csv
import dataclasses
from pathlib import Path
from typing import Any

import numpy as np
import pytest

from neurov import _core, load_scenario, simulate
from neurov.results.decimation import PlotRows, for_plotting
from neurov.results.timeseries import SERIES
from neurov.running.stream import stream_run
from neurov.config.scenario import ControllerSpec
from neurov.running.plant import build_vehicle

ROOT = Path(__file__).resolve().parents[2]
SCENARIOS = ROOT / "examples" / "scenarios"


def _rows(path: Path) -> list[list[str]]:
    with path.open(newline="") as f:
        return list(csv.reader(f))


def _same_metrics(a: dict[str, Any], b: dict[str, Any]) -> None:
    """Equal to 1e-12 relative: the chunks' sums add in another order."""
    assert a.keys() == b.keys()
    for key in a:
        if isinstance(a[key], dict):
            _same_metrics(a[key], b[key])
        elif isinstance(a[key], (float, list)):
            np.testing.assert_allclose(a[key], b[key], rtol=1e-12, atol=0, err_msg=key)
        else:
            assert a[key] == b[key], key


@pytest.mark.parametrize("name", ["thrusters_failure.toml", "sea_state_4_pickup.toml", "lawnmower_pd_current.toml"])
def test_streamed_files_are_the_whole_runs(name: str, tmp_path: Path) -> None:
    scenario = load_scenario(SCENARIOS / name).replace(duration=60.0)
    whole = simulate(scenario)
    run = stream_run(scenario, tmp_path, chunk_rows=7)
    assert [p.name for p in run.written] == ["result.csv", "result.npz"]
    whole.to_csv(tmp_path / "whole.csv")
    assert _rows(tmp_path / "result.csv") == _rows(tmp_path / "whole.csv")
    whole.to_npz(tmp_path / "whole.npz")
    with np.load(tmp_path / "result.npz", allow_pickle=False) as got, \
            np.load(tmp_path / "whole.npz", allow_pickle=False) as expected:
        assert sorted(got.files) == sorted(expected.files)
        for key in expected.files:
            np.testing.assert_array_equal(got[key], expected[key], err_msg=key)
    _same_metrics(run.metrics, whole.metrics())
    for key in SERIES:  # 301 rows: drawn whole
        np.testing.assert_array_equal(getattr(run.drawn, key), getattr(whole, key), err_msg=key)
    assert run.sea == (name != "thrusters_failure.toml")
    if scenario.waves is not None:
        assert run.elevation is not None
        np.testing.assert_array_equal(run.elevation.wave_elevation, whole.wave_elevation)
    assert not list(tmp_path.glob(".result.npz.*")), "the spool of the NPZ is left behind"


def test_chunks_keep_the_rows_the_whole_run_draws() -> None:
    whole = simulate(load_scenario(SCENARIOS / "thrusters_failure.toml").replace(duration=2000.0))
    plot_rows = PlotRows(len(whole.t), whole.thrusts.shape[1], max_rows=1000)
    step = plot_rows.chunk_rows(1234)
    assert step % plot_rows.bucket == 0
    for start in range(0, len(whole.t), step):
        plot_rows.add(dataclasses.replace(whole, **{k: getattr(whole, k)[start:start + step] for k in SERIES}))
    drawn, expected = plot_rows.result(), for_plotting(whole, max_rows=1000)
    assert len(drawn.t) < 1000 and drawn.extra["plotted_rows_of"] == len(whole.t)
    for key in SERIES:
        np.testing.assert_array_equal(getattr(drawn, key), getattr(expected, key), err_msg=key)


def test_a_diverging_stream_keeps_every_row(tmp_path: Path) -> None:
    scenario = load_scenario(SCENARIOS / "square_nn.toml").replace(
        duration=20.0, controller=ControllerSpec("pd", label="hot", kp=[1e7] * 6, kd=[1e7] * 6))
    whole = simulate(scenario)
    assert whole.diverged
    run = stream_run(scenario, tmp_path, chunk_rows=3)
    assert run.drawn.diverged and run.metrics["diverged"]
    assert len(_rows(tmp_path / "result.csv")) == len(whole.t) + 1
    _same_metrics(run.metrics, whole.metrics())


class Hold:
    """A Python controller: a constant force."""

    def step(self, eta: Any, nu: Any, eta_d: Any, eta_d_dot: Any, eta_d_ddot: Any) -> np.ndarray:
        return np.array([5.0, 0.0, 1.0, 0.0, 0.0, 0.5])


def test_a_python_controller_streams_through_the_simulator(tmp_path: Path) -> None:
    from neurov.running.stepper import Simulator

    scenario = load_scenario(SCENARIOS / "lawnmower_pd_current.toml").replace(duration=30.0)
    whole = Simulator(scenario).run(Hold())
    assert not whole.controller_status.any()  # the force is applied, no step refused
    chunks: list[dict[str, Any]] = []
    sim = Simulator(scenario, log_rows=40)
    assert len(sim.run(Hold(), on_rows=chunks.append).t) == 0
    assert [len(c["t"]) for c in chunks] == [40, 40, 40, 31]
    for key in SERIES:
        np.testing.assert_array_equal(np.concatenate([c[key] for c in chunks]), getattr(whole, key), err_msg=key)
    full = Simulator(scenario, log_rows=10)
    for _ in range(10):
        full.step(np.zeros(6))
    with pytest.raises(RuntimeError, match="log window of 10 rows is full"):
        full.step(np.zeros(6))
    assert full.steps == 10


def test_bad_chunk_rows_are_named(tmp_path: Path) -> None:
    scenario = load_scenario(SCENARIOS / "square_nn.toml").replace(duration=5.0)
    for bad in (0, -3, 2.5):
        with pytest.raises(ValueError, match="argument 'chunk_rows' must be an int >= 1"):
            stream_run(scenario, chunk_rows=bad)  # type: ignore[arg-type]
    with pytest.raises(ValueError, match="chunk_rows"):
        _core.run_closed_loop_chunks(build_vehicle(scenario), _core.PDController(
            _core.PDConfig(kp=[1.0] * 6, kd=[1.0] * 6)), scenario.simulation, 0, lambda rows: None)
    with pytest.raises(ValueError, match="log_rows"):
        _core.Simulator(build_vehicle(scenario), scenario.simulation, 0, -1)


def test_an_error_in_the_sink_ends_the_run_and_propagates() -> None:
    scenario = load_scenario(SCENARIOS / "square_nn.toml").replace(duration=50.0)
    seen: list[int] = []

    def stop(rows: dict[str, Any]) -> None:
        seen.append(len(rows["t"]))
        raise KeyboardInterrupt

    vehicle = build_vehicle(scenario)
    with pytest.raises(KeyboardInterrupt):
        _core.run_closed_loop_chunks(vehicle, _core.PDController(_core.PDConfig(kp=[1.0] * 6, kd=[1.0] * 6)),
                                     scenario.simulation, 20, stop)
    assert seen == [20]



def test_the_run_shows_its_progress_on_a_terminal(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    import io
    import sys

    class Terminal(io.StringIO):
        def isatty(self) -> bool:
            return True

    scenario = load_scenario(SCENARIOS / "square_nn.toml").replace(duration=20.0)
    monkeypatch.setattr(sys, "stderr", tty := Terminal())
    stream_run(scenario, tmp_path, quiet=False, chunk_rows=30)
    shown = tty.getvalue()
    assert "run" in shown and "101/101" in shown and "result.npz" in shown
    monkeypatch.setattr(sys, "stderr", tty := Terminal())
    stream_run(scenario, tmp_path)  # quiet by default
    assert tty.getvalue() == ""
