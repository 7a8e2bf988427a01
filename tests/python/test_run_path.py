"""One way through a run (docs/architecture.md, "The way through a run"): a
scenario's config is built once and checked once, rebuilt and checked again
only when it changed; ``neurov run --out`` checks its folder once."""

from __future__ import annotations

import sys
from collections import Counter
from pathlib import Path
from typing import Any

import numpy as np
import pytest

import neurov
from neurov import _core
from neurov.config.reading import load_scenario
from neurov.config.scenario import CommandSpec, Scenario, scenario_path
from neurov.running import folder as run_folder
from neurov.running import stream as run_stream
from neurov.running.command import run_scenario_file
from neurov.running.plant import simulation_config

ROOT = Path(__file__).resolve().parents[2]


@pytest.fixture
def counted(monkeypatch: pytest.MonkeyPatch) -> Counter[str]:
    """How often the scenario's config is built and validated, and the
    output folder checked, while a test runs."""
    counts: Counter[str] = Counter()

    def counting(owner: Any, name: str) -> None:
        original = getattr(owner, name)

        def call(*args: Any, **kwargs: Any) -> Any:
            counts[name] += 1
            return original(*args, **kwargs)

        monkeypatch.setattr(owner, name, call)

    counting(Scenario, "_sync")
    counting(_core.SimulationConfig, "validate")
    counting(run_folder, "check_output_dir")
    counting(run_stream, "check_output_dir")
    return counts


def test_a_run_of_a_scenario_file_builds_and_checks_its_config_once(counted: Counter[str], tmp_path: Path,
                                                                     capsys: pytest.CaptureFixture[str]) -> None:
    run_scenario_file(scenario_path("paper_fig3"), out_dir=tmp_path / "run")
    assert counted == {"_sync": 1, "validate": 1, "check_output_dir": 1}
    assert (tmp_path / "run" / "result.csv").is_file()


def test_a_scenario_is_built_and_checked_again_only_when_it_changed(counted: Counter[str]) -> None:
    scenario = load_scenario(scenario_path("paper_fig3"))
    simulation_config(scenario)
    simulation_config(scenario)
    assert counted == {"_sync": 1, "validate": 1}
    scenario.dt = 0.1  # changed through the scenario: checked again, not rebuilt
    simulation_config(scenario)
    assert counted == {"_sync": 1, "validate": 2}
    scenario.command.args["side"] = 3.0  # the command spec changed in place: rebuilt and checked
    config = simulation_config(scenario)
    assert counted == {"_sync": 2, "validate": 3}
    assert np.max(np.abs(config.command.poses[:, :2])) == pytest.approx(3.0)


def test_a_config_handed_out_is_checked_again(counted: Counter[str]) -> None:
    scenario = load_scenario(scenario_path("paper_fig3"))
    scenario.simulation.substeps = 0
    with pytest.raises(ValueError, match="substeps = 0"):
        neurov.simulate(scenario)
    assert counted["validate"] == 2


def test_a_copy_keeps_the_config_built(counted: Counter[str]) -> None:
    scenario = Scenario(command=CommandSpec("square", {"side": 4.0}), duration=20.0)
    copy = scenario.replace(seed=3)
    assert counted["_sync"] == 1
    assert copy.simulation.command.poses.tolist() == scenario.simulation.command.poses.tolist()
    other = scenario.replace(command=CommandSpec("square", {"side": 6.0}))
    assert counted["_sync"] == 2
    assert np.max(np.abs(other.simulation.command.poses[:, :2])) == pytest.approx(6.0)


def test_the_call_path_tool_counts_a_run(tmp_path: Path) -> None:
    sys.path.insert(0, str(ROOT / "tools"))
    try:
        import call_path
    finally:
        sys.path.remove(str(ROOT / "tools"))
    path, status = call_path.measure(["run", "paper_fig3", "--out", str(tmp_path / "run")])
    assert status == 0
    assert path.calls == path.stays + len(path.per_module) + path.returns > 100
    assert path.by_name["neurov.config.scenario:Scenario._sync"] == 1
    assert path.by_name["neurov.running.folder:check_output_dir"] == 1
    assert path.by_name[call_path.VALIDATE] == 1
