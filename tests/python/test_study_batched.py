"""A study whose factory makes a batched policy steps each worker's runs of a
scenario in one call per step, with the same runs.csv as the same law run
per run; a run the policy fails in is the only failed run."""

from __future__ import annotations

import os
from pathlib import Path

import pandas as pd
import pytest

from neurov.study import run_study
from test_study_factory import write

# The factories importable here and in the workers (conftest.py).
pytestmark = pytest.mark.usefixtures("user_controllers_importable")


def _mine(name: str) -> str:
    return f'factory = "user_controllers.factories:{name}"\nlabel = "numpy PD"'


def test_a_batched_policy_gives_the_table_of_the_same_law_run_per_run(tmp_path: Path) -> None:
    tables = {}
    for name in ("numpy_pd", "batched_numpy_pd"):
        folder = tmp_path / name
        folder.mkdir()
        # One worker, one batch: the three samples of each scenario are one batch of the policy.
        run_study(write(folder, _mine(name)), folder / "out", executor="processes", workers=1, batch_size=12,
                  progress=False, plots=False)
        tables[name] = (folder / "out" / "runs.csv").read_text()
    assert tables["numpy_pd"] == tables["batched_numpy_pd"]
    rows = pd.read_csv(tmp_path / "numpy_pd" / "out" / "runs.csv")
    assert len(rows) == 12 and rows.notna().all().all()


def test_a_run_the_batched_policy_fails_in_is_the_only_failed_run(tmp_path: Path) -> None:
    out = run_study(write(tmp_path, _mine("fails_on_second_run_alone")), tmp_path / "out", executor="processes",
                    workers=1, batch_size=12, progress=False, plots=False)
    rows = out.table[out.table.controller == "mine"]
    failed = rows[rows.rmse_position_m.isna()]
    assert set(failed.error_kind) == {"error"} and failed.error.str.contains("this policy fails").all()
    assert rows[rows.rmse_position_m.notna()].error_kind.isna().all()
    # Per scenario (a batch of three samples), the second run alone is the one that failed.
    assert sorted(zip(failed.scenario, failed["sample"])) == [("a", 1), ("b", 1)]


def _calls(path: Path) -> list[tuple[int, str]]:
    return [(int(pid), name) for pid, name in (line.split() for line in path.read_text().splitlines())]


@pytest.mark.parametrize(("workers", "batch_size"), [(1, 12), (2, 3)])
def test_a_per_run_factory_is_called_once_per_run(tmp_path: Path, monkeypatch: pytest.MonkeyPatch,
                                                  workers: int, batch_size: int) -> None:
    """Once per run in the workers, however the runs are batched (learning
    that it makes no batched policy costs no call of its own), and once per
    scenario where the study is read."""
    calls = tmp_path / "calls.txt"
    monkeypatch.setenv("NEUROV_TEST_CALLS_FILE", str(calls))
    out = run_study(write(tmp_path, _mine("counted_numpy_pd")), tmp_path / "out", executor="processes",
                    workers=workers, batch_size=batch_size, progress=False, plots=False)
    assert out.table.rmse_position_m.notna().all()
    here = [name for pid, name in _calls(calls) if pid == os.getpid()]
    in_workers = [name for pid, name in _calls(calls) if pid != os.getpid()]
    assert sorted(here) == ["a", "b"]
    assert sorted(in_workers) == ["a"] * 3 + ["b"] * 3  # three samples of each scenario


def test_a_batched_factory_is_called_once_per_scenario_of_a_batch(tmp_path: Path,
                                                                  monkeypatch: pytest.MonkeyPatch) -> None:
    """Its one product steps the batch's three runs of a scenario."""
    calls = tmp_path / "calls.txt"
    monkeypatch.setenv("NEUROV_TEST_CALLS_FILE", str(calls))
    out = run_study(write(tmp_path, _mine("counted_batched_numpy_pd")), tmp_path / "out", executor="processes",
                    workers=1, batch_size=12, progress=False, plots=False)
    assert out.table.rmse_position_m.notna().all()
    in_workers = [name for pid, name in _calls(calls) if pid != os.getpid()]
    assert sorted(in_workers) == ["a", "b"]
