"""Every count a file or a call can give has a maximum, refused before
anything is allocated or run, the message giving the limit (issue 23;
docs/reliability.md): substeps (2e9 ran for ever), NN centres (10^8 grew to
24 GB), wave components (10^9 refused without the limit)."""

from __future__ import annotations

import time
from pathlib import Path

import numpy as np
import pytest

import neurov
from neurov import _core, centres
from neurov.config.reading import load_scenario
from neurov.config.scenario import ScenarioError
from neurov.study import StudyError, load_study

SCENARIO = """
duration = 1.0
{top}
[command]
type = "waypoints"
times = [0.0]
poses = [[0, 0, 0, 0, 0, 0]]
[controller]
{controller}
{tables}
"""
PD = 'type = "pd"'
NN = 'type = "nn"\n[controller.centres]\n'


def _scenario(tmp_path: Path, top: str = "", controller: str = PD, tables: str = "") -> Path:
    path = tmp_path / "s.toml"
    path.write_text(SCENARIO.format(top=top, controller=controller, tables=tables), encoding="utf-8")
    return path


def test_the_limits_are_the_cores() -> None:
    assert (neurov.MAX_SUBSTEPS, neurov.MAX_CENTRES, neurov.MAX_WAVE_COMPONENTS) == (10000, 65536, 512)


@pytest.mark.parametrize(
    ("where", "text", "field", "limit"),
    [
        pytest.param("top", "substeps = 10001", "substeps", "10000", id="substeps over"),
        pytest.param("top", "substeps = 2000000000", "substeps", "10000", id="substeps 2e9"),
        pytest.param("top", "substeps = 20000000000", "substeps", "10000", id="substeps beyond an int"),
        pytest.param("controller", NN + "n = 100000000", "controller.centres.n", "65536", id="centres 1e8"),
        pytest.param("controller", NN + 'method = "grid"\naxes = { eta_x = [-1, 1, 1000], eta_y = [-1, 1, 1000] }',
                     "controller.centres.axes", "65536", id="grid of 1e6"),
        pytest.param("tables", "[waves]\ncomponents = 513", "waves.components", "512", id="waves over"),
        pytest.param("tables", "[waves]\ncomponents = 1000000000", "waves.components", "512", id="waves 1e9"),
        pytest.param("tables", "[waves]\ncomponents = 10000000000", "waves.components", "512",
                     id="waves beyond an int"),
    ],
)
def test_a_count_over_its_limit_is_refused_naming_file_field_and_limit(
        tmp_path: Path, where: str, text: str, field: str, limit: str) -> None:
    path = _scenario(tmp_path, **{where: text})
    with pytest.raises(ScenarioError) as err:
        load_scenario(path)
    message = str(err.value)
    assert str(path) in message and field in message and limit in message, message


def test_a_study_refuses_a_controller_of_too_many_centres(tmp_path: Path) -> None:
    path = tmp_path / "study.toml"
    path.write_text('scenarios = ["nerov_square"]\n[controllers.nn]\ntype = "nn"\n'
                    "[controllers.nn.centres]\nn = 100000000\n", encoding="utf-8")
    with pytest.raises((StudyError, ScenarioError)) as err:
        load_study(path)
    assert "65536" in str(err.value) and str(path) in str(err.value), str(err.value)


@pytest.mark.parametrize(
    "make",
    [
        pytest.param(lambda: centres.sobol(10**8, -1, 1), id="sobol"),
        pytest.param(lambda: centres.latin_hypercube(10**8, -1, 1), id="latin_hypercube"),
        # 10^12 points on one axis: refused before the axis is made (8 TB).
        pytest.param(lambda: centres.grid({"eta_x": (-1, 1, 10**12)}), id="grid"),
    ],
)
def test_centre_placement_refuses_more_than_a_network_takes_before_making_them(make) -> None:
    start = time.perf_counter()
    with pytest.raises(ValueError, match="more than the 65536 a network takes"):
        make()
    assert time.perf_counter() - start < 1.0


def test_a_network_of_too_many_centres_is_refused_naming_the_limit() -> None:
    with pytest.raises(ValueError, match=r"centres = 65537: expected at most 65536 centres"):
        neurov.RbfNetwork(np.zeros((neurov.MAX_CENTRES + 1, 24)), 1.0)


def test_the_simulation_config_validator_gives_the_substeps_limit() -> None:
    config = neurov.SimulationConfig()
    config.command = _core.Command(times=[0.0], poses=np.zeros((1, 6)))
    config.substeps = 2_000_000_000
    with pytest.raises(ValueError, match=r"substeps = 2e\+09: expected a whole number in 1..10000"):
        config.validate()


def test_a_run_at_the_substeps_limit_is_bounded(tmp_path: Path) -> None:
    """1 s at 5 Hz with 10^4 substeps: 5 x 10^4 RK4 steps, well under a
    second (docs/reliability.md has the time of a longer run)."""
    scenario = load_scenario(_scenario(tmp_path, top=f"substeps = {neurov.MAX_SUBSTEPS}"))
    start = time.perf_counter()
    result = neurov.simulate(scenario)
    assert time.perf_counter() - start < 10.0
    assert len(result.t) == 6 and np.all(np.isfinite(result.eta))


def test_a_study_of_more_runs_than_it_holds_is_refused_at_once(tmp_path: Path) -> None:
    from neurov.study.spec import MAX_RUNS

    path = tmp_path / "study.toml"
    path.write_text('scenarios = ["nerov_square", "nerov_helix"]\nsamples = 1000000000\n'
                    '[controllers.pd]\ntype = "pd"\n', encoding="utf-8")
    with pytest.raises(StudyError) as err:  # when the file is read, before any run's key is made
        load_study(path)
    message = str(err.value)
    assert str(path) in message and "samples" in message and f"{MAX_RUNS}" in message, message
    path.write_text(path.read_text().replace("1000000000", str(MAX_RUNS // 2)), encoding="utf-8")
    assert load_study(path).samples == MAX_RUNS // 2
