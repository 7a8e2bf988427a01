"""Numbers that mean something else (issue 23, item 8): a seed outside the
core's 64-bit range is told with the range wherever it enters, and a time
step too small for the duration is blamed on dt."""

from __future__ import annotations

from pathlib import Path

import pytest

import neurov
from neurov import _core
from neurov.config.scenario import SCENARIO_DIR, ScenarioError

RANGE = r"must be >= 0 and <= 18446744073709551615, got "


def short() -> neurov.Scenario:
    return neurov.load_scenario(SCENARIO_DIR / "paper_fig3.toml").replace(duration=1.0)


def test_a_seed_of_2_to_the_63_runs_and_one_past_the_range_gives_it(tmp_path: Path) -> None:
    sim = neurov.Simulator(short())
    sim.reset(2**63)  # the core's seeds are uint64, as SimulationConfig.seed already took them
    sim.reset(2**64 - 1)
    for bad in (2**64, -1):
        with pytest.raises(ValueError, match=r"argument 'seed' " + RANGE + str(bad)):
            sim.reset(bad)
    with pytest.raises(ValueError, match=r"SimulationConfig.seed " + RANGE + "18446744073709551616"):
        short().replace(seed=2**64)
    text = (SCENARIO_DIR / "paper_fig3.toml").read_text()
    path = tmp_path / "big_seed.toml"
    path.write_text(text.replace("\nseed = 0", "\nseed = 18446744073709551616", 1))
    with pytest.raises(ScenarioError, match=r"big_seed\.toml: seed: " + RANGE):
        neurov.load_scenario(path)


def test_a_tiny_dt_is_blamed_on_dt_and_a_huge_duration_on_duration(tmp_path: Path) -> None:
    for dt in (5e-324, 1e-7):
        with pytest.raises(ValueError, match=r"dt = .*>= duration / 1e8"):
            _core.SimulationConfig(dt=dt, duration=250.0).validate()
    with pytest.raises(ValueError, match=r"duration = .*at most 1e9 s"):
        _core.SimulationConfig(dt=10.0, duration=2e9).validate()
    text = (SCENARIO_DIR / "paper_fig3.toml").read_text()
    path = tmp_path / "tiny_dt.toml"
    path.write_text(text.replace("dt = 0.2", "dt = 5e-324"))
    with pytest.raises(ScenarioError, match=r"tiny_dt\.toml: dt = "):
        neurov.simulate(neurov.load_scenario(path))
