"""NN centres along the commanded path (centres.method = "path"): they are
the inputs a run on its desired trajectory sees, one per stretch of the
duration, fixed by the seed; a scenario or tuning file selects them."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

import neurov
from neurov.laws.registry import input_normalisation, make_centres
from neurov.laws.path_centres import along_path, path_inputs
from neurov.errors import ScenarioError

SCENARIO = """
name = "short_square"
duration = 20.0
dt = 0.1
[vehicle]
preset = "nerov"
[command]
type = "waypoints"
times = [0.0, 5.0, 10.0, 15.0]
poses = [[0, 0, 1, 0, 0, 0], [2, 0, 1, 0, 0, 0], [2, 2, 1, 0, 0, 1.5], [0, 2, 1, 0, 0, 3.0]]
[controller]
type = "nn"
width = 3.0
[controller.centres]
method = "path"
n = 16
seed = 4
"""


@pytest.fixture
def scenario(tmp_path: Path) -> neurov.Scenario:
    path = tmp_path / "s.toml"
    path.write_text(SCENARIO)
    return neurov.load_scenario(path)


def test_path_centres_are_the_desired_trajectorys_inputs_one_per_stretch(scenario: neurov.Scenario) -> None:
    t, inputs = path_inputs(scenario)
    assert inputs.shape == (201, 24) and t[-1] == pytest.approx(20.0)
    # Along the desired trajectory of the loop itself: eta_d of a run, and nu = nu_r = nu_d.
    run = neurov.simulate(scenario)
    np.testing.assert_allclose(inputs[:, 18:], run.eta_d, atol=1e-9)
    np.testing.assert_array_equal(inputs[:, 6:12], inputs[:, 12:18])
    centres = along_path(scenario, 16, seed=4)
    rows = [int(np.flatnonzero(np.all(inputs == c, axis=1))[0]) for c in centres]  # each a path input
    # One in each sixteenth of the 20 s (the nearest step of a time drawn in it).
    assert all(i * 12.5 - 0.5 <= r <= (i + 1) * 12.5 + 0.5 for i, r in enumerate(rows)), rows
    # The spec builds them so, and the seed fixes them.
    spec = scenario.controller
    np.testing.assert_array_equal(make_centres(spec, np.zeros(24), np.ones(24), scenario), centres)
    np.testing.assert_array_equal(along_path(scenario, 16, seed=4), centres)
    assert not np.array_equal(along_path(scenario, 16, seed=5), centres)
    # With normalised inputs the centres are where the network sees the path.
    normalised = spec.replace()
    normalised.options["inputs"] = "normalised"
    offset, scale = input_normalisation(scenario)
    np.testing.assert_allclose(make_centres(normalised, np.zeros(24), np.ones(24), scenario),
                               (centres - offset) * scale)
    with pytest.raises(ValueError, match="give the scenario"):
        make_centres(spec, np.zeros(24), np.ones(24))


def test_a_path_network_runs_and_a_box_is_refused_with_it(tmp_path: Path) -> None:
    path = tmp_path / "s.toml"
    path.write_text(SCENARIO)
    assert np.isfinite(neurov.simulate(neurov.load_scenario(path)).metrics()["rmse_position_m"])
    path.write_text(SCENARIO.replace("seed = 4\n", "seed = 4\nlow = " + str([0.0] * 24) + "\n"))
    with pytest.raises(ScenarioError, match="controller.centres") as e:
        neurov.load_scenario(path)
    assert "low" in str(e.value)
    path.write_text(SCENARIO.replace('method = "path"', 'method = "along"'))
    with pytest.raises(ScenarioError, match="'path'"):
        neurov.load_scenario(path)


def test_a_tuning_searches_the_placement_of_the_centres(tmp_path: Path) -> None:
    pytest.importorskip("optuna")
    import pandas as pd
    from test_tune import TUNING, write

    from neurov.tuning import TuneError, load_tuning, tune

    text = TUNING.replace('''[controllers.pd]
type = "pd"
kp = [20, 20, 20, 2, 2, 2]
kd = [25, 25, 40, 1, 1, 1]
[controllers.pd.search]
kp = { scale = [0.05, 20.0], log = true }''', '''[controllers.nn]
type = "nn"
width = 3.0
[controllers.nn.centres]
n = 16
[controllers.nn.search]
"centres.method" = { choices = ["sobol", "path"] }''')
    tuning = load_tuning(write(tmp_path, trials=4, tuning=text))
    tune(tuning, tmp_path / "out", workers=1, verdict=False, plots=False, progress=False)
    table = pd.read_csv(tmp_path / "out" / "trials.csv")
    assert set(table["param_centres.method"]) <= {"sobol", "path"} and len(table) == 4
    assert np.isfinite(table["objective"]).all()
    bad = text.replace('choices = ["sobol", "path"]', 'choices = ["sobol", "along"]')
    with pytest.raises(TuneError, match="centres.method"):
        load_tuning(write(tmp_path, trials=4, tuning=bad))
