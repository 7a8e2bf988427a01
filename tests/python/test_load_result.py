"""neurov.load_result: a run read back from its folder, its NPZ, CSV or
Parquet file equals the run (every array to the last bit, its scenario, its
metrics); bad files are refused naming the file and what was expected."""

from __future__ import annotations

import csv
import json
import zipfile
from pathlib import Path
from typing import Any

import numpy as np
import pytest

import neurov
from neurov.results.columns import RESULT_SERIES, SERIES
from neurov.errors import ResultFileError
from neurov.results.timeseries import Result
from neurov.running.command import run_scenario_file
from neurov.running.folder import finite_or_none
from neurov.config.reading import load_scenario

# A few seconds of a BlueROV2 Heavy on its thrusters, with sensors, the EKF,
from neurov.config.scenario import scenario_path
# waves, a current, a sinusoidal disturbance, a failing thruster and the
# linear adaptive controller (its theta columns): every kind of column.
SEA = """
name = "load_back"
duration = 3.0
dt = 0.2
substeps = 4
seed = 3
water_density = 1025.0

[vehicle]
preset = "bluerov2_heavy"
thrusters = true

[initial]
eta = [0, 0, 1.0, 0, 0, 0]

[command]
type = "square"
side = 4.0
speed = 0.25
depth = 1.0
start = 0.5

[controller]
type = "linear"
theta0 = "true"
kd = [50, 50, 75, 1.5, 1.5, 1.5]

[[disturbances]]
dof = "yaw"
amplitude = 0.5
frequency = 0.5

[current]
velocity = [0.2, 0.1, 0.0]

[waves]
spectrum = "jonswap"
hs = 0.88
tp = 7.5
components = 12

[[thruster_failures]]
index = 2
efficiency = 0.5
time = 1.0

[sensors]
usbl = { rate = 1.0, noise = 0.5, latency = 0.5 }
dvl = { rate = 5.0, noise = 0.01, dropout_rate = 0.2 }
depth = { rate = 10.0, noise = 0.02 }
imu = { rate = 50.0, attitude_noise = 0.005, gyro_noise = 0.001, gyro_bias_walk = 1e-5 }

[estimator]
type = "ekf"
"""


def assert_same_run(loaded: Result, run: Result) -> None:
    for name in SERIES:
        got, want = getattr(loaded, name), getattr(run, name)
        assert got.dtype == want.dtype and got.shape == want.shape, name
        np.testing.assert_array_equal(got, want, err_msg=name)  # NaN where NaN
    assert loaded.controller == run.controller and loaded.diverged == run.diverged
    assert loaded.scenario.describe() == run.scenario.describe()


@pytest.fixture(scope="module")
def folder(tmp_path_factory: pytest.TempPathFactory) -> tuple[Path, Result, dict[str, Any]]:
    tmp = tmp_path_factory.mktemp("load")
    (tmp / "load_back.toml").write_text(SEA, encoding="utf-8")
    result, metrics = run_scenario_file(tmp / "load_back.toml", out_dir=tmp / "run")
    result.to_parquet(tmp / "run" / "result.parquet")
    return tmp / "run", result, metrics


def test_the_scenario_has_every_kind_of_column(folder: tuple[Path, Result, dict[str, Any]]) -> None:
    _, run, _ = folder
    assert run.thrusts.shape[1] == 8 and run.theta.shape[1] == len(neurov.THETA_NAMES)
    assert np.any(run.wave_velocity) and np.any(run.faults) and np.any(run.disturbance)
    assert not np.array_equal(run.eta_estimate, run.eta)


@pytest.mark.parametrize("name", ["", "result.npz", "result.csv", "result.parquet"])
def test_a_run_folder_and_each_file_load_back(folder: tuple[Path, Result, dict[str, Any]], name: str) -> None:
    out, run, _ = folder
    loaded = neurov.load_result(out / name if name else out)
    assert_same_run(loaded, run)
    assert loaded.scenario.name == "load_back"


def test_the_metrics_recomputed_are_the_written_ones(folder: tuple[Path, Result, dict[str, Any]]) -> None:
    out, _, _ = folder
    written = json.loads((out / "metrics.json").read_text())
    for name in ("result.npz", "result.csv"):
        recomputed = finite_or_none(neurov.load_result(out / name).metrics())
        assert recomputed == {k: written[k] for k in recomputed}


@pytest.fixture(scope="module")
def paper() -> Result:
    return neurov.simulate(load_scenario(scenario_path("paper_fig3")).replace(duration=4.0))


@pytest.mark.parametrize("writer", ["to_npz", "to_csv", "to_parquet"])
def test_paper_fig3_loads_back_from_each_format(paper: Result, tmp_path: Path, writer: str) -> None:
    path = getattr(paper, writer)(tmp_path / f"r.{writer.removeprefix('to_')}")
    with pytest.raises(ResultFileError, match=r"r\.\w+: the file holds no scenario.*scenario="):
        neurov.load_result(path)
    loaded = neurov.load_result(path, scenario=paper.scenario)
    assert_same_run(loaded, paper)
    assert loaded.metrics() == paper.metrics()


def test_the_csv_header_is_t_and_the_pandas_columns(paper: Result, tmp_path: Path) -> None:
    import pandas as pd

    frame = paper.to_pandas()
    with paper.to_csv(tmp_path / "r.csv").open(newline="") as f:
        header = next(csv.reader(f))
    assert header == ["t", *frame.columns]
    back = pd.read_csv(tmp_path / "r.csv", index_col="t")
    for name in frame.columns:  # the same values: numbers, status names, fault bits
        if isinstance(frame[name].dtype, pd.CategoricalDtype):
            assert back[name].astype(str).tolist() == frame[name].astype(str).tolist(), name
        else:
            np.testing.assert_array_equal(back[name].to_numpy(), frame[name].to_numpy(), err_msg=name)
    assert list(frame["controller_status"].cat.categories) == list(neurov.Status.__members__)


def test_the_cpp_table_is_the_one_list(paper: Result) -> None:
    import ast
    import dataclasses

    names = [entry[0] for entry in neurov._core.RESULT_SERIES]
    assert tuple(names) == SERIES == tuple(s.name for s in RESULT_SERIES)
    fields = [f.name for f in dataclasses.fields(Result)]
    assert fields[fields.index("t"):fields.index("diverged")] == names
    config = neurov.running.plant.simulation_config(paper.scenario)
    raw = neurov.run_closed_loop(neurov.running.plant.build_vehicle(paper.scenario),
                                 neurov.laws.registry.build_controller(paper.scenario.controller, paper.scenario),
                                 config)
    assert list(raw) == [*names, "diverged"]
    for spec in RESULT_SERIES:
        assert raw[spec.name].dtype == np.dtype(spec.dtype), spec.name
        if spec.width is not None and spec.width > 1:
            assert raw[spec.name].shape[1] == spec.width == len(spec.labels), spec.name
    stub = ast.parse((Path(neurov.__file__).parent / "_core.pyi").read_text())
    typed = next(n for n in stub.body if isinstance(n, ast.ClassDef) and n.name == "_SimulationResult")
    keys = [n.target.id for n in typed.body if isinstance(n, ast.AnnAssign) and isinstance(n.target, ast.Name)]
    assert keys == [*names, "diverged"]


def test_bad_files_are_refused_naming_them(folder: tuple[Path, Result, dict[str, Any]], tmp_path: Path) -> None:
    import pandas as pd

    out, run, _ = folder
    with pytest.raises(ResultFileError, match=r"nowhere: no such file or folder"):
        neurov.load_result(tmp_path / "nowhere")
    (tmp_path / "r.txt").write_text("t\n0\n")
    with pytest.raises(ResultFileError, match=r"r\.txt: unknown kind of result file '\.txt'.*\.npz, \.csv, \.parquet"):
        neurov.load_result(tmp_path / "r.txt")
    with pytest.raises(ResultFileError, match=r"a folder without a run's result file"):
        neurov.load_result(tmp_path)
    frame = pd.read_csv(out / "result.csv")
    frame.drop(columns=["eta_psi"]).to_csv(tmp_path / "cut.csv", index=False)
    with pytest.raises(ResultFileError, match=r"cut\.csv: missing column\(s\) \['eta_psi'\]"):
        neurov.load_result(tmp_path / "cut.csv", scenario=run.scenario)
    frame.to_csv(tmp_path / "indexed.csv")  # pandas' own index column, unnamed
    with pytest.raises(ResultFileError, match=r"indexed\.csv: unexpected column\(s\) \['Unnamed: 0'\]"):
        neurov.load_result(tmp_path / "indexed.csv", scenario=run.scenario)
    frame.assign(plant_status="exploded").to_csv(tmp_path / "status.csv", index=False)
    with pytest.raises(ResultFileError, match=r"status\.csv: column 'plant_status': unknown status 'exploded'"):
        neurov.load_result(tmp_path / "status.csv", scenario=run.scenario)
    with pytest.raises(ResultFileError, match=r"result\.csv: 8 thrust columns, but scenario 'paper_fig3' has 6 thrusters"):
        neurov.load_result(out / "result.csv", scenario="paper_fig3")
    arrays = {k: getattr(run, k) for k in SERIES}
    np.savez(tmp_path / "narrow.npz", **{**arrays, "eta": run.eta[:, :5]})
    with pytest.raises(ResultFileError, match=r"narrow\.npz: array 'eta' is float64 \(16, 5\), expected float64 \(16, 6\)"):
        neurov.load_result(tmp_path / "narrow.npz", scenario=run.scenario)
    np.savez(tmp_path / "short.npz", **{k: v for k, v in arrays.items() if k != "faults"})
    with pytest.raises(ResultFileError, match=r"short\.npz: array 'faults' is missing"):
        neurov.load_result(tmp_path / "short.npz", scenario=run.scenario)
    (tmp_path / "broken.npz").write_bytes((out / "result.npz").read_bytes()[:500])
    with pytest.raises(ResultFileError, match=r"broken\.npz: not a \.npz archive"):
        neurov.load_result(tmp_path / "broken.npz", scenario=run.scenario)
    assert zipfile.is_zipfile(out / "result.npz")


def test_a_stopped_run_is_not_a_diverged_one(folder: tuple[Path, Result, dict[str, Any]], tmp_path: Path) -> None:
    import pandas as pd

    out, run, _ = folder
    kept = tmp_path / "run.partial"  # what a Ctrl-C leaves: some CSV rows and a partial metrics.json
    kept.mkdir()
    pd.read_csv(out / "result.csv").iloc[:5].to_csv(kept / "result.csv", index=False)
    (kept / "metrics.json").write_text(json.dumps({"scenario": "load_back", "controller": "linear",
                                                   "partial": True}))
    loaded = neurov.load_result(kept, scenario=run.scenario)
    assert len(loaded.t) == 5 and not loaded.diverged
    (kept / "metrics.json").unlink()
    assert neurov.load_result(kept, scenario=run.scenario).diverged  # fewer rows, nothing says stopped


def test_a_recording_loads_back_as_the_run_that_wrote_it(tmp_path: Path) -> None:
    pytest.importorskip("mcap_ros2")
    scenario = neurov.load_scenario(scenario_path("paper_fig3"))
    scenario.duration = 4.0
    result = neurov.simulate(scenario)
    result.to_mcap(tmp_path / "run.mcap")
    back = neurov.load_result(tmp_path / "run.mcap", scenario=scenario)
    for name in SERIES:
        np.testing.assert_array_equal(getattr(back, name), getattr(result, name), err_msg=name)
    assert back.metrics() == result.metrics()
