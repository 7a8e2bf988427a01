"""Real runs, real failures (issue 15): a diverged run keeps its evidence, the
metrics have one window, outputs are checked before the work, long runs are
written in blocks and drawn decimated, messages name what was wrong."""

from __future__ import annotations

import csv
import dataclasses
import json
import math
import sys
from pathlib import Path

import numpy as np
import pytest

from neurov import cli
from neurov.paper import experiments as paper
from neurov.results.decimation import for_plotting, kept_rows
from neurov.results.timeseries import SERIES, TRANSIENT_S, metrics_start
from neurov.config.reading import load_scenario
from neurov.results.timeseries import Result
from neurov.running.simulation import simulate
from square_pd import square_pd_scenario

ROOT = Path(__file__).resolve().parents[2]

# PD gains of 10^7 on NEROV at 5 Hz: the plant overflows within the first second.
DIVERGING = square_pd_scenario("diverging_pd", 60.0, substeps=5, gain="1e7")


@pytest.fixture
def diverging(tmp_path: Path) -> Path:
    path = tmp_path / "diverging.toml"
    path.write_text(DIVERGING, encoding="utf-8")
    return path


def test_diverging_run_keeps_its_evidence(diverging: Path, tmp_path: Path,
                                          capsys: pytest.CaptureFixture[str]) -> None:
    out = tmp_path / "out"
    assert cli.main(["run", str(diverging), "--out", str(out), "--plot"]) == 3
    captured = capsys.readouterr()
    result = simulate(load_scenario(diverging))
    assert result.diverged and 1 < len(result.t) < 301 and result.t[-1] < 1.0
    line = f"diverged at t = {result.t[-1]:g} s: plant status non_finite_output"
    assert line in captured.out and line in captured.err and "exit status 3" in captured.err
    assert "leaves no samples" not in captured.out + captured.err
    # Everything simulated is written.
    names = {p.name for p in out.iterdir()}
    assert {"result.csv", "result.npz", "metrics.json", "xy.png", "dofs.png", "errors.png", "inputs.png",
            "adaptive_norm.png"} <= names
    with (out / "result.csv").open(newline="") as f:
        assert len(list(csv.reader(f))) == len(result.t) + 1
    with np.load(out / "result.npz") as data:
        assert bool(data["diverged"]) and len(data["t"]) == len(result.t)
    # The metrics cover those rows, flagged.
    m = json.loads((out / "metrics.json").read_text())
    assert m["diverged"] is True and m["diverged_at_s"] == pytest.approx(result.t[-1])
    assert m["window_start_s"] == 0.0 and m["window_end_s"] == pytest.approx(result.t[-1])
    pos = np.linalg.norm(result.error[:, :3], axis=1)
    assert m["max_position_error_m"] == pytest.approx(np.max(pos), rel=1e-12)


def test_diverged_paper_run_is_written_flagged_and_exits_3(tmp_path: Path, monkeypatch: pytest.MonkeyPatch,
                                                           capsys: pytest.CaptureFixture[str]) -> None:
    shipped = paper.paper_scenario

    def short_and_unstable(name: str):  # type: ignore[no-untyped-def]
        s = shipped(name)
        # Without its saturating thrusters, K_d = 10^7 at 5 Hz overflows the plant at once.
        return s.replace(duration=4.0, use_thrusters=False,
                         controller=s.controller.replace(kd=np.full(6, 1e7)))

    monkeypatch.setattr(paper, "paper_scenario", short_and_unstable)
    out = tmp_path / "paper"
    assert cli.main(["paper", "--out", str(out)]) == 3
    err = capsys.readouterr().err
    metrics = json.loads((out / "metrics.json").read_text())
    bad = paper.diverged_runs(metrics)
    assert "fig3_nn" in bad and "fig3_nn_kd0" not in bad and "fig3_nn" in err
    assert {"fig3_xy.png", "fig4_inputs.png", "fig5_yaw_disturbance.png", "summary.md"} <= {
        p.name for p in out.iterdir()}
    assert metrics["fig3_nn"]["diverged_at_s"] < 4.0


def test_one_metrics_window_stated_everywhere(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    assert TRANSIENT_S == 10.0
    assert metrics_start(86400.0) == 10.0 and metrics_start(600.0) == 10.0 and metrics_start(12.0) == 6.0
    scenario = load_scenario(ROOT / "examples" / "scenarios" / "square_nn.toml").replace(duration=30.0)
    path = tmp_path / "s.toml"
    path.write_text((ROOT / "examples" / "scenarios" / "square_nn.toml").read_text()
                    .replace("duration = 250.0", "duration = 30.0"), encoding="utf-8")
    assert cli.main(["run", str(path), "--out", str(tmp_path / "o")]) == 0
    assert "metrics over 10 s <= t <= 30 s" in capsys.readouterr().out
    written = json.loads((tmp_path / "o" / "metrics.json").read_text())
    result = simulate(scenario)
    assert written["window_start_s"] == 10.0 and written["rmse"] == result.metrics()["rmse"]
    assert result.metrics() == result.metrics(after=10.0)
    from neurov.plotting import runs as plots

    fig = plots.errors(result)
    legend = [t.get_text() for t in fig.axes[0].get_legend().get_texts()]
    assert legend == [f"NN adaptive (RMS {result.metrics()['rmse']['x']:.3g} m over t ≥ 10 s)"]


def test_out_is_checked_before_anything_runs(diverging: Path, tmp_path: Path, monkeypatch: pytest.MonkeyPatch,
                                             capsys: pytest.CaptureFixture[str]) -> None:
    import neurov.running.command

    def no_run(*args: object, **kwargs: object) -> None:
        raise AssertionError("simulated before checking --out")

    monkeypatch.setattr(neurov.running.command, "stream_run", no_run)
    monkeypatch.setattr(paper, "run_experiments", no_run)
    a_file = tmp_path / "a_file"
    a_file.write_text("x")
    assert cli.main(["run", str(diverging), "--out", str(a_file)]) == 1
    assert "'" + str(a_file) + "' is an existing file" in capsys.readouterr().err
    assert cli.main(["run", str(diverging), "--out", str(a_file / "sub")]) == 1
    assert "cannot be created" in capsys.readouterr().err
    assert cli.main(["paper", "--out", str(a_file)]) == 1
    assert "is an existing file" in capsys.readouterr().err
    assert a_file.read_text() == "x"


def test_nan_initial_pose_is_named(tmp_path: Path) -> None:
    scenario = load_scenario(ROOT / "examples" / "scenarios" / "square_nn.toml")
    with pytest.raises(ValueError, match=r"'eta0' \(the initial pose\) must be 6 finite numbers") as e:
        simulate(scenario.replace(eta0=np.array([0.0, math.nan, 0.0, 0.0, 0.0, 0.0])))
    assert "'low' and 'high'" not in str(e.value)


def test_run_help_points_at_a_page_and_states_the_exit_status(capsys: pytest.CaptureFixture[str]) -> None:
    with pytest.raises(SystemExit) as e:
        cli.main(["run", "--help"])
    assert e.value.code == 0
    out = capsys.readouterr().out
    assert "docs/running.md" in out and "neurov.config.scenario" not in out
    assert "3    a run diverged" in out and (ROOT / "docs" / "running.md").is_file()


@pytest.fixture(scope="module")
def long_run() -> Result:
    """10,001 rows of a PD hold, with a one-sample spike in yaw moment."""
    r = simulate(load_scenario(ROOT / "examples" / "scenarios" / "lawnmower_pd_current.toml")
                 .replace(duration=2000.0))
    tau = r.tau_demanded.copy()
    tau[7777, 5] = 1e6
    return dataclasses.replace(r, tau_demanded=tau)


def test_decimated_plot_rows_keep_every_extreme(long_run: Result) -> None:
    assert for_plotting(long_run) is long_run  # 10,001 rows: drawn whole
    keep = kept_rows(long_run, max_rows=1000)
    assert len(keep) <= 1000 and np.all(np.diff(keep) > 0) and keep[0] == 0 and keep[-1] == len(long_run.t) - 1
    assert 7777 in keep
    drawn = for_plotting(long_run, max_rows=1000)
    assert drawn.extra["plotted_rows_of"] == len(long_run.t)
    for name in SERIES:
        np.testing.assert_array_equal(getattr(drawn, name), getattr(long_run, name)[keep], err_msg=name)
    # The envelope is exact per bucket: every bucket's extremes of each drawn quantity are drawn.
    size = -(-len(long_run.t) // (1000 // (2 * (30 + long_run.thrusts.shape[1] + 1) + 2)))
    for values in (long_run.eta, long_run.error, long_run.tau_demanded, long_run.adaptive_norm[:, None]):
        for start in range(0, len(long_run.t), size):
            block = values[start:start + size]
            inside = (keep >= start) & (keep < start + size)
            np.testing.assert_array_equal(values[keep[inside]].max(axis=0), block.max(axis=0))
            np.testing.assert_array_equal(values[keep[inside]].min(axis=0), block.min(axis=0))


@pytest.mark.parametrize("writer", ["pyarrow", "csv module"])
def test_csv_written_in_blocks_reads_back_exactly(long_run: Result, tmp_path: Path, writer: str,
                                                  monkeypatch: pytest.MonkeyPatch) -> None:
    import neurov.results.export

    if writer == "pyarrow":
        pytest.importorskip("pyarrow")
    else:
        monkeypatch.setitem(sys.modules, "pyarrow", None)  # import pyarrow raises ImportError
    monkeypatch.setattr(neurov.results.export, "CSV_BLOCK_ROWS", 997)
    run = dataclasses.replace(long_run, **{k: getattr(long_run, k)[:5000] for k in SERIES})
    path = run.to_csv(tmp_path / "r.csv")
    with path.open(newline="") as f:
        rows = list(csv.reader(f))
    cols = run.columns()
    assert rows[0] == list(cols) and len(rows) == 5001
    # Numbers read back to the same float64, statuses as their names.
    for k, name in enumerate(rows[0]):
        col = [r[k] for r in rows[1:]]
        want = cols[name]
        if want.dtype.kind == "U":
            assert col == want.tolist(), name
        else:
            np.testing.assert_array_equal(np.array(col, dtype=np.float64), want, err_msg=name)


def test_diverged_study_run_is_a_failed_row(diverging: Path, tmp_path: Path,
                                            capsys: pytest.CaptureFixture[str]) -> None:
    import pandas as pd

    (tmp_path / "study.toml").write_text(f"""
name = "unstable"
samples = 1
after = 5.0
scenarios = ["{diverging.name}"]

[controllers.hot]
type = "pd"
kp = 1e7
kd = 1e7

[controllers.calm]
type = "pd"
kp = [100, 100, 100, 50, 50, 50]
kd = [200, 200, 200, 50, 50, 50]
""", encoding="utf-8")
    out = tmp_path / "out"
    assert cli.main(["study", str(tmp_path / "study.toml"), "--out", str(out), "--workers", "1",
                     "--executor", "processes", "--no-plots", "--quiet"]) == 0
    runs = pd.read_csv(out / "runs.csv").set_index("controller")
    assert runs.loc["hot", "diverged"] == 1 and runs.loc["hot", "failed"]
    assert math.isinf(runs.loc["hot", "rmse_position_m"]) and math.isinf(runs.loc["hot", "iae_z"])
    assert runs.loc["calm", "diverged"] == 0 and math.isfinite(runs.loc["calm", "rmse_position_m"])
    # Counted apart from the runs that raised, in the summary and the league table.
    summary = pd.read_csv(out / "summary.csv").set_index("controller")
    assert summary.loc["hot", "failed_diverged"] == 1 and summary.loc["hot", "failed_error"] == 0
    assert summary.loc["calm", "failed_diverged"] == 0
    league = (out / "league.md").read_text()
    assert "| 2 | hot | inf | 100 % | 0 | 1 |" in league, league  # one plant: no 5th-95th percentile column


def test_writing_and_plotting_show_progress_on_a_terminal(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    import io

    from neurov.running.command import write_outputs

    class Terminal(io.StringIO):
        def isatty(self) -> bool:
            return True

    result = simulate(load_scenario(ROOT / "examples" / "scenarios" / "square_nn.toml").replace(duration=20.0))
    tty = Terminal()
    monkeypatch.setattr(sys, "stderr", tty)
    write_outputs(result, result.metrics(), tmp_path, plot=True, quiet=False)
    shown = tty.getvalue()
    assert "result.csv" in shown and f"{len(result.t)}/{len(result.t)}" in shown
    assert "result.npz" in shown and "figures" in shown and "5/5" in shown
    monkeypatch.setattr(sys, "stderr", tty := Terminal())
    write_outputs(result, result.metrics(), tmp_path, plot=True)  # quiet by default
    assert tty.getvalue() == ""
