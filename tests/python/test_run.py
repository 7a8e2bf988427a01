"""neurov.running.command.run_scenario_file, what `neurov run SCENARIO.toml [--out DIR] [--plot]` calls."""

from __future__ import annotations

import csv
import inspect
import json
from pathlib import Path

import numpy as np
import pytest

from neurov.running.command import FIGURES, run_scenario_file
from neurov.config.scenario import ScenarioError

ROOT = Path(__file__).resolve().parents[2]

SCENARIO = """
name = "short_square"
duration = 10.0
dt = 0.2
substeps = 5

[vehicle]
preset = "nerov"
thrusters = true

[command]
type = "square"
side = 2.0
start = 1.0

[controller]
type = "nn"
[controller.centres]
n = 16
"""


@pytest.fixture
def scenario_file(tmp_path: Path) -> Path:
    path = tmp_path / "short.toml"
    path.write_text(SCENARIO, encoding="utf-8")
    return path


def test_signature_the_cli_relies_on() -> None:
    params = inspect.signature(run_scenario_file).parameters
    assert list(params) == ["path", "out_dir", "plot", "file_format"]
    assert params["out_dir"].default is None and params["plot"].default is False
    assert params["file_format"].default == "csv"


def test_prints_metrics_after_the_transient(scenario_file: Path, capsys: pytest.CaptureFixture[str]) -> None:
    result, metrics = run_scenario_file(scenario_file)
    out = capsys.readouterr().out
    assert "short_square" in out and "NN adaptive" in out
    # The one metrics window (neurov.results.timeseries.metrics_start): 10 s, or half a run shorter than 20 s.
    assert "metrics over 5 s <= t <= 10 s" in out and "transient" in out
    assert "RMS position error" in out
    assert metrics["window_start_s"] == pytest.approx(5.0) and metrics["window_end_s"] == pytest.approx(10.0)
    expected = result.metrics(after=5.0)
    assert {k: metrics[k] for k in expected} == expected == result.metrics()
    assert metrics["rmse_position_m"] != result.metrics(after=0.0)["rmse_position_m"]
    assert metrics["scenario"] == "short_square" and metrics["controller"] == "NN adaptive"


def test_no_files_without_out_dir(scenario_file: Path, tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.chdir(tmp_path)
    run_scenario_file(scenario_file)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["short.toml"]


def test_writes_results(scenario_file: Path, tmp_path: Path) -> None:
    out = tmp_path / "out" / "deeper"
    result, metrics = run_scenario_file(scenario_file, out_dir=out)
    assert sorted(p.name for p in out.iterdir()) == ["metrics.json", "result.csv", "result.npz", "scenario.toml"]
    assert json.loads((out / "metrics.json").read_text()) == metrics
    assert (out / "scenario.toml").read_bytes() == scenario_file.read_bytes()
    with (out / "result.csv").open(newline="") as f:
        rows = list(csv.reader(f))
    assert rows[0][0] == "t" and len(rows) == len(result.t) + 1 == 52
    with np.load(out / "result.npz") as data:
        np.testing.assert_array_equal(data["eta"], result.eta)
        np.testing.assert_array_equal(data["thrusts"], result.thrusts)


def test_writes_figures(scenario_file: Path, tmp_path: Path) -> None:
    run_scenario_file(scenario_file, out_dir=tmp_path, plot=True)
    assert set(FIGURES) == {"xy.png", "dofs.png", "errors.png", "inputs.png", "adaptive_norm.png"}
    for name in FIGURES:
        data = (tmp_path / name).read_bytes()
        assert data[:4] == b"\x89PNG" and len(data) > 5000, name


def test_plot_needs_out_dir(scenario_file: Path) -> None:
    with pytest.raises(ValueError, match="out_dir"):
        run_scenario_file(scenario_file, plot=True)


def test_bad_file_is_a_scenario_error(tmp_path: Path) -> None:
    path = tmp_path / "bad.toml"
    path.write_text(SCENARIO.replace('type = "nn"', 'type = "fuzzy"'), encoding="utf-8")
    with pytest.raises(ScenarioError, match=r"bad\.toml: controller\.type"):
        run_scenario_file(path, out_dir=tmp_path / "out")
    assert not (tmp_path / "out").exists()


def test_diverged_metrics_are_valid_json(tmp_path: Path) -> None:
    # A diverged run has infinite errors; JSON has no Infinity, so null.
    from neurov.running.folder import finite_or_none

    text = json.dumps(finite_or_none({"a": float("inf"), "b": [1.0, float("nan")], "c": {"d": 2}}),
                      allow_nan=False)
    assert json.loads(text) == {"a": None, "b": [1.0, None], "c": {"d": 2}}


def test_example_through_the_cli(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    cli = pytest.importorskip("neurov.cli")
    example = ROOT / "examples" / "scenarios" / "lawnmower_pd_current.toml"
    short = tmp_path / "lawn.toml"
    short.write_text(example.read_text().replace("duration = 480.0", "duration = 20.0"), encoding="utf-8")
    assert cli.main(["run", str(short), "--out", str(tmp_path / "o")]) == 0
    assert "lawnmower_pd_current" in capsys.readouterr().out
    assert (tmp_path / "o" / "metrics.json").is_file()
    assert cli.main(["run", str(tmp_path / "missing.toml")]) == 1
    assert "missing.toml" in capsys.readouterr().err


def test_a_shipped_scenario_runs_by_name(capsys: pytest.CaptureFixture[str]) -> None:
    cli = pytest.importorskip("neurov.cli")
    assert cli.main(["run", "paper_fig3"]) == 0
    assert "scenario 'paper_fig3'" in capsys.readouterr().out
    assert cli.main(["run", "paper_fig9"]) == 1
    err = capsys.readouterr().err
    assert "paper_fig9: no such scenario file, and no shipped scenario of that name" in err and "paper_fig3" in err


def test_plot_without_out_prints_the_run_usage(scenario_file: Path, capsys: pytest.CaptureFixture[str]) -> None:
    cli = pytest.importorskip("neurov.cli")
    with pytest.raises(SystemExit) as stop:
        cli.main(["run", str(scenario_file), "--plot"])
    assert stop.value.code == 2
    err = capsys.readouterr().err
    assert err.startswith("usage: neurov run ") and "--plot needs --out DIR" in err


def test_python_dash_m_neurov_is_the_command() -> None:
    import subprocess
    import sys

    import neurov

    env = {**__import__("os").environ, "PYTHONPATH": str(Path(neurov.__file__).resolve().parents[1])}
    done = subprocess.run([sys.executable, "-m", "neurov", "--version"], capture_output=True, text=True, env=env)
    assert done.returncode == 0 and done.stdout.startswith(f"neurov {neurov.__version__}")


def test_refused_steps_before_the_window_are_counted_and_said(tmp_path: Path,
                                                              capsys: pytest.CaptureFixture[str]) -> None:
    cli = pytest.importorskip("neurov.cli")
    path = tmp_path / "dropout.toml"
    # A 1 s sensor dropout in the first half: all 5 refused steps before the window (t >= 2 s).
    path.write_text(SCENARIO.replace("duration = 10.0", "duration = 4.0")
                    + '\n[[sensor_faults]]\nkind = "dropout"\nstart = 1.0\nend = 2.0\n', encoding="utf-8")
    assert cli.main(["run", str(path), "--out", str(tmp_path / "o")]) == 0
    captured = capsys.readouterr()
    assert "refused controller steps  5 (0 in the window)" in captured.out
    line = "5 of 21 controller steps were refused (0 in the metrics window), the first at t = 1 s, non_finite_input"
    assert f"warning: {line}" in captured.out and f"neurov: warning: {line}" in captured.err
    m = json.loads((tmp_path / "o" / "metrics.json").read_text())
    assert m["refused_steps"] == 5 and m["refused_steps_in_window"] == 0
    assert m["first_refusal"] == "t = 1 s, non_finite_input"
