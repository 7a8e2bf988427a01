"""Scenario files: every shipped and example file loads and runs; a bad file
is a ScenarioError naming the file, the field and what was expected."""

from __future__ import annotations

import math
import re
import shutil
from pathlib import Path

import numpy as np
import pytest

from neurov.config.reading import load_scenario
from neurov.config.scenario import ScenarioError
from neurov.running.simulation import simulate
from neurov.config.vehicle_file import preset_path

ROOT = Path(__file__).resolve().parents[2]
EXAMPLES = sorted((ROOT / "examples" / "scenarios").glob("*.toml"))
SHIPPED = sorted((ROOT / "python" / "neurov" / "scenarios").glob("*.toml"))


def test_the_examples_are_there() -> None:
    # The parametrised test below would pass vacuously on an empty folder.
    names = {p.stem for p in EXAMPLES}
    assert {"square_nn", "helix_linear", "lawnmower_pd_current", "thrusters_failure",
            "noise_yaw_disturbance"} <= names


@pytest.mark.parametrize("path", EXAMPLES + SHIPPED, ids=lambda p: f"{p.parent.name}/{p.name}")
def test_scenario_file_loads_and_runs(path: Path) -> None:
    scenario = load_scenario(path)
    assert scenario.source == str(path)
    assert scenario.duration > 0
    result = simulate(scenario.replace(duration=12.0))
    assert len(result.t) == round(12.0 / scenario.dt) + 1
    assert not result.diverged
    m = result.metrics()
    assert math.isfinite(m["rmse_position_m"]) and math.isfinite(m["max_abs_tau"])


def test_example_contents() -> None:
    """The examples do what their names say."""
    by_name = {p.stem: load_scenario(p) for p in EXAMPLES}
    s = by_name["square_nn"]
    assert (s.command.type, s.controller.type, s.vehicle) == ("square", "nn", "nerov")
    s = by_name["helix_linear"]
    assert (s.command.type, s.controller.type) == ("helix", "linear")
    s = by_name["lawnmower_pd_current"]
    assert (s.command.type, s.controller.type) == ("lawnmower", "pd")
    assert np.linalg.norm(s.current) == pytest.approx(0.3)
    s = by_name["thrusters_failure"]
    assert s.use_thrusters and s.saturation.name == "clip"
    assert [(f.index, f.efficiency, f.time) for f in s.thruster_failures] == [(0, 0.0, 60.0)]
    s = by_name["noise_yaw_disturbance"]
    assert np.all(s.noise_eta > 0) and np.all(s.noise_nu > 0)
    assert [d.dof for d in s.disturbances] == [5]


# --- reading -----------------------------------------------------------------------

MINIMAL = """
name = "t"
duration = 10.0

[command]
type = "square"
side = 4.0

[controller]
type = "pd"
kp = 100.0
kd = [200, 200, 200, 50, 50, 50]
"""


def write(tmp_path: Path, text: str, name: str = "s.toml") -> Path:
    path = tmp_path / name
    path.write_text(text, encoding="utf-8")
    return path


def test_minimal_file_and_defaults(tmp_path: Path) -> None:
    s = load_scenario(write(tmp_path, MINIMAL))
    assert s.name == "t" and s.duration == 10.0 and s.dt == 0.2 and s.substeps == 10
    assert s.vehicle == "nerov" and not s.use_thrusters
    np.testing.assert_array_equal(s.controller.kp, np.full(6, 100.0))
    assert s.command.args == {"side": 4.0}
    np.testing.assert_array_equal(s.eta0, 0.0)
    assert not s.disturbances and not s.thruster_failures


def test_name_defaults_to_the_file_stem(tmp_path: Path) -> None:
    s = load_scenario(write(tmp_path, MINIMAL.replace('name = "t"', ""), "my_run.toml"))
    assert s.name == "my_run"


def test_dof_names_and_indices(tmp_path: Path) -> None:
    text = MINIMAL + """
[[disturbances]]
dof = "yaw"
amplitude = 5.0
frequency = 0.1
[[disturbances]]
dof = 1
amplitude = -2.0
"""
    s = load_scenario(write(tmp_path, text))
    assert [(d.dof, d.amplitude, d.frequency) for d in s.disturbances] == [(5, 5.0, 0.1), (1, -2.0, 0.0)]


def test_vehicle_file_relative_to_the_scenario(tmp_path: Path) -> None:
    (tmp_path / "boats").mkdir()
    shutil.copy(preset_path("nerov"), tmp_path / "boats" / "mine.toml")
    text = MINIMAL + '\n[vehicle]\nfile = "boats/mine.toml"\nthrusters = true\n'
    s = load_scenario(write(tmp_path, text))
    assert s.vehicle_path() == tmp_path / "boats" / "mine.toml"
    result = simulate(s.replace(duration=1.0))
    assert result.thrusts.shape == (6, 6)


# --- errors: the file, the field, what was expected ----------------------------------


def replace_line(old: str, new: str) -> str:
    assert old in MINIMAL
    return MINIMAL.replace(old, new)


BAD = {
    "missing controller": (
        MINIMAL.split("[controller]")[0],
        ["controller", "missing", "type"],
    ),
    "misspelt field": (
        replace_line("duration = 10.0", "durration = 10.0"),
        ["durration", "unknown field", "did you mean 'duration'"],
    ),
    "misspelt field in a table": (
        replace_line('kd = [200', 'kdd = [200'),
        ["controller.kdd", "did you mean 'kd'"],
    ),
    "wrong type": (
        replace_line("duration = 10.0", 'duration = "long"'),
        ["duration", "expected a number", "str"],
    ),
    "wrong length": (
        MINIMAL + "\n[initial]\neta = [0, 0, 0]\n",
        ["initial.eta", "expected 6 numbers", "got 3"],
    ),
    "unknown controller type": (
        replace_line('type = "pd"', 'type = "mpc"'),
        ["controller.type", "expected one of", "'nn'", "'mpc'"],
    ),
    "unknown dof name": (
        MINIMAL + '\n[[disturbances]]\ndof = "yawn"\namplitude = 1.0\n',
        ["disturbances[0].dof", "'yaw'", "0..5", "'yawn'"],
    ),
    "negative noise": (
        MINIMAL + "\n[noise]\neta = [0.1, 0.1, -0.1, 0, 0, 0]\n",
        ["noise.eta", ">= 0"],
    ),
    "failure efficiency above 1": (
        MINIMAL + "\n[vehicle]\nthrusters = true\n[[thruster_failures]]\nindex = 0\nefficiency = 1.5\n",
        ["thruster_failures[0].efficiency", "[0, 1]", "1.5"],
    ),
    "failures without thrusters": (
        MINIMAL + "\n[[thruster_failures]]\nindex = 0\ntime = 5.0\n",
        ["thruster_failures[0]", "a thruster configuration"],
    ),
    "invalid toml": (
        MINIMAL + "\n[controller\n",
        ["not valid TOML"],
    ),
    "missing vehicle file": (
        MINIMAL + '\n[vehicle]\nfile = "nowhere.toml"\n',
        ["vehicle", "nowhere.toml", "no such vehicle file"],
    ),
    "unknown preset": (
        MINIMAL + '\n[vehicle]\npreset = "titanic"\n',
        ["vehicle", "titanic", "nerov"],
    ),
    "unknown trajectory": (
        replace_line('type = "square"', 'type = "spiral"'),
        ["command.type", "expected one of", "'spiral'"],
    ),
    "bad trajectory argument": (
        replace_line("side = 4.0", "sides = 4.0"),
        ["command", "square", "sides"],
    ),
    "negative duration": (
        replace_line("duration = 10.0", "duration = -1.0"),
        ["duration", "> 0"],
    ),
}


@pytest.mark.parametrize("case", sorted(BAD))
def test_bad_file(tmp_path: Path, case: str) -> None:
    text, fragments = BAD[case]
    path = write(tmp_path, text)
    with pytest.raises(ScenarioError) as info:
        load_scenario(path)
    message = str(info.value)
    assert message.startswith(str(path)), message
    for fragment in fragments:
        assert fragment in message, f"{fragment!r} not in {message!r}"


def test_misspelt_field_next_to_the_right_one(tmp_path: Path) -> None:
    # A stray key beside the right one is reported with a hint too.
    path = write(tmp_path, MINIMAL.replace("duration = 10.0", "duration = 10.0\ndurration = 3.0"))
    with pytest.raises(ScenarioError, match=r"durration: unknown field; did you mean 'duration'\?"):
        load_scenario(path)


def test_missing_scenario_file(tmp_path: Path) -> None:
    with pytest.raises(ScenarioError, match=re.escape(str(tmp_path / "gone.toml")) + ".*no such"):
        load_scenario(tmp_path / "gone.toml")


def test_scenario_error_is_a_value_error() -> None:
    # The CLI turns ValueErrors into a one-line message without a traceback.
    assert issubclass(ScenarioError, ValueError)
