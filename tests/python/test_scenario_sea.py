"""The sea in scenario files: [current] model = "gauss_markov", [waves] and
[[payload]] go into the bound C++ structs; bad input is named by file, TOML
key, value and what was expected."""

from __future__ import annotations

import copy
import pickle
import sys
from pathlib import Path

import numpy as np
import pytest

from neurov import _core
from neurov.config.scenario import ScenarioError
from neurov.config.reading import read_scenario, scenario_from_mapping
from neurov.schema import as_dict
from neurov.running.simulation import simulate
from neurov.study.spec import SCENARIO_DIR

if sys.version_info >= (3, 11):
    import tomllib
else:  # pragma: no cover
    import tomli as tomllib

ROOT = Path(__file__).resolve().parents[2]
BASE = tomllib.loads((SCENARIO_DIR / "nerov_square.toml").read_text())

SEA = {
    "current": {"model": "gauss_markov", "speed": 0.4, "speed_std": 0.05, "time_constant": 20.0,
                "speed_min": 0.1, "speed_max": 1.5, "direction": 45.0, "direction_std": 5.0,
                "vertical_angle": 2.0, "vertical_angle_std": 1.0},
    "waves": {"spectrum": "pierson_moskowitz", "hs": 1.5, "tp": 7.0, "gamma": 2.0, "direction": 30.0,
              "spreading": 2.0, "components": 150},
    "payload": [{"time": 10.0, "mass": 5.0, "buoyancy": 2.0, "mass_position": [0.3, 0.0, 0.1],
                 "buoyancy_position": [0.3, 0.0, 0.1], "damping_scale": [1.1, 1, 1, 1, 1, 1.2],
                 "added_mass_scale": 1.05},
                {"time": 20.0, "mass": -5.0}],
}


def scenario(**tables: object):
    data = copy.deepcopy(BASE)
    data.update(copy.deepcopy(tables))
    return scenario_from_mapping(data, "sea.toml")


def test_every_key_lands_in_its_bound_field() -> None:
    c = scenario(**SEA).simulation
    assert c.current_model == _core.CurrentModel.gauss_markov
    gm = c.gauss_markov_current
    for key, value in SEA["current"].items():
        if key != "model":
            assert getattr(gm, key) == value, key
    w = c.waves
    assert w.spectrum == _core.WaveSpectrum.pierson_moskowitz
    for key, value in SEA["waves"].items():
        if key != "spectrum":
            assert getattr(w, key) == value, key
    first, second = c.payload
    assert (first.time, first.mass, first.buoyancy, first.added_mass_scale) == (10.0, 5.0, 2.0, 1.05)
    np.testing.assert_array_equal(first.mass_position, [0.3, 0.0, 0.1])
    np.testing.assert_array_equal(first.buoyancy_position, [0.3, 0.0, 0.1])
    np.testing.assert_array_equal(first.damping_scale, [1.1, 1, 1, 1, 1, 1.2])
    assert (second.time, second.mass, second.mass_position, second.buoyancy_position) == (20.0, -5.0, None, None)


def test_absent_keys_take_the_cpp_defaults() -> None:
    c = scenario(current={"model": "gauss_markov"}, waves={}, payload=[{"time": 3.0}]).simulation
    assert as_dict(c.gauss_markov_current) == as_dict(_core.GaussMarkovCurrentConfig())
    assert as_dict(c.waves) == as_dict(_core.WaveConfig())
    assert as_dict(c.payload[0]) == as_dict(_core.PayloadEvent(time=3.0))
    calm = scenario().simulation
    assert calm.current_model == _core.CurrentModel.constant and calm.waves is None and calm.payload == ()
    # model = "constant" is today's current, keys and all.
    c = scenario(current={"model": "constant", "velocity": [0.2, 0.1, 0.0]}).simulation
    assert c.current_model == _core.CurrentModel.constant
    np.testing.assert_array_equal(c.current, [0.2, 0.1, 0.0])


def test_the_sea_survives_describe_replace_and_pickle() -> None:
    s = scenario(**SEA)
    d = s.describe()["simulation"]
    assert d["current_model"] == "gauss_markov"
    assert d["gauss_markov_current"]["time_constant"] == 20.0
    assert d["waves"] == {**SEA["waves"]}
    assert [e["time"] for e in d["payload"]] == [10.0, 20.0]
    assert d["payload"][0]["mass_position"] == [0.3, 0.0, 0.1] and d["payload"][1]["mass_position"] is None
    # Two scenarios that differ only in the sea describe (and so hash) apart.
    assert scenario(**{**SEA, "waves": {**SEA["waves"], "hs": 1.6}}).describe() != s.describe()
    back = pickle.loads(pickle.dumps(s))
    assert back.describe() == s.describe()
    t = s.replace(waves=None, current_model="constant", payload=[])
    assert t.waves is None and t.current_model == _core.CurrentModel.constant and t.payload == ()
    assert s.waves.hs == 1.5 and len(s.payload) == 2  # the copy has its own config


def test_a_scenario_file_runs_its_sea(tmp_path: Path) -> None:
    # The file's sea reaches the run: the current, the waves and the payload.
    s = scenario(**SEA, initial={"eta": [0, 0, 3.0, 0, 0, 0]})
    r = simulate(s.replace(duration=30.0))
    assert np.all(np.linalg.norm(r.current, axis=1) > 0)
    assert np.ptp(r.wave_elevation) > 0.5 and np.any(r.wave_velocity != 0)
    np.testing.assert_array_equal(r.payload_mass, np.where(r.t >= 20.0, 0.0, np.where(r.t >= 10.0, 5.0, 0.0)))


BAD = [
    # (tables, expected message): the issue's list, each by file and key
    ({"waves": {"hs": 0.0}}, r"sea\.toml: waves\.hs = 0: expected > 0"),
    ({"waves": {"hs": -1.0}}, r"sea\.toml: waves\.hs = -1: expected > 0"),
    ({"waves": {"tp": 0.0}}, r"sea\.toml: waves\.tp = 0: expected > 0"),
    ({"waves": {"gamma": 0.9}}, r"sea\.toml: waves\.gamma = 0\.9: expected >= 1"),
    ({"waves": {"components": 0}}, r"sea\.toml: waves\.components = 0: expected within \[1,"),
    ({"waves": {"spreading": -2.0}}, r"sea\.toml: waves\.spreading = -2: expected >= 0"),
    ({"current": {"model": "gauss_markov", "time_constant": 0.0}},
     r"sea\.toml: current\.time_constant = 0: expected > 0"),
    ({"current": {"model": "gauss_markov", "time_constant": -5.0}},
     r"sea\.toml: current\.time_constant = -5: expected > 0"),
    ({"current": {"model": "gauss_markov", "speed_std": -0.1}},
     r"sea\.toml: current\.speed_std = -0\.1: expected >= 0"),
    ({"current": {"model": "gauss_markov", "direction_std": -1.0}},
     r"sea\.toml: current\.direction_std = -1: expected >= 0"),
    ({"current": {"model": "gauss_markov", "speed_min": 1.0, "speed_max": 0.5, "speed": 0.7}},
     r"sea\.toml: current\.speed_max = 0\.5: expected >= speed_min"),
    ({"current": {"model": "gauss_markov", "speed": 3.0}},
     r"sea\.toml: current\.speed = 3: expected within \[speed_min, speed_max\]"),
    ({"current": {"model": "gauss_markov", "vertical_angle": 95.0}},
     r"sea\.toml: current\.vertical_angle = 95: expected within \[-90, 90\]"),
    ({"payload": [{"time": 5.0, "mass": -185.0}]},
     r"sea\.toml: payload\[0\]\.mass = -185: expected > -\(the vehicle's mass\)"),
    ({"payload": [{"time": 5.0, "mass": -100.0}, {"time": 6.0, "mass": -90.0}]},
     r"sea\.toml: payload\[1\]\.mass = -90: expected > -\(the vehicle's mass\)"),
    ({"payload": [{"time": 5.0, "buoyancy": -2000.0}]},
     r"sea\.toml: payload\[0\]\.buoyancy = -2000: expected >= -\(the vehicle's buoyancy\)"),
    ({"payload": [{"time": 5.0}, {"time": 4.0}]},
     r"sea\.toml: payload\[1\]\.time = 4: expected >= 0, finite and non-decreasing"),
    ({"payload": [{"time": -1.0}]}, r"sea\.toml: payload\[0\]\.time = -1: expected >= 0"),
    ({"payload": [{"time": 1.0, "added_mass_scale": -1.0}]},
     r"sea\.toml: payload\[0\]\.added_mass_scale = -1: expected >= 0"),
    # unknown keys, with a suggestion
    ({"waves": {"tpp": 8.0}}, r"sea\.toml: waves\.tpp: unknown field; did you mean 'tp'\?"),
    ({"current": {"model": "gauss_markov", "time_constnat": 3.0}},
     r"sea\.toml: current\.time_constnat: unknown field; did you mean 'time_constant'\?"),
    ({"payload": [{"time": 1.0, "mas": 2.0}]}, r"sea\.toml: payload\[0\]\.mas: unknown field; did you mean 'mass'\?"),
    # keys of the other current model
    ({"current": {"model": "gauss_markov", "velocity": [0.5, 0, 0]}},
     r"sea\.toml: current\.velocity: is a key of model = \"constant\""),
    ({"current": {"speed": 0.5}}, r"sea\.toml: current\.speed: is a key of model = \"gauss_markov\""),
    ({"current": {"model": "gauss_markov"}, "current_steps": [{"time": 5.0, "velocity": [0.1, 0, 0]}]},
     r"sea\.toml: current_steps: expected none with current\.model = \"gauss_markov\""),
    # wrong types
    ({"waves": {"hs": "2 m"}}, r"sea\.toml: waves\.hs: expected a number, got str '2 m'"),
    ({"waves": {"components": 100.0}}, r"sea\.toml: waves\.components: expected an integer, got float 100\.0"),
    ({"waves": {"spectrum": "bretschneider"}},
     r"sea\.toml: waves\.spectrum: expected one of \['jonswap', 'pierson_moskowitz'\], got 'bretschneider'"),
    ({"waves": [1, 2]}, r"sea\.toml: waves: expected a table, got list"),
    ({"current": {"model": 1}}, r"sea\.toml: current\.model: expected a string, got int 1"),
    ({"current": {"model": "gauss-markov"}},
     r"sea\.toml: current\.model: expected one of \['constant', 'gauss_markov'\], got 'gauss-markov'"),
    ({"current": {"model": "gauss_markov", "speed": True}}, r"sea\.toml: current\.speed: expected a number, got bool"),
    ({"payload": {"time": 1.0}}, r"sea\.toml: payload: expected an array of tables \[\[payload\]\]"),
    ({"payload": [{"time": "noon"}]}, r"sea\.toml: payload\[0\]\.time: expected a number, got str 'noon'"),
    ({"payload": [{"time": 1.0, "mass_position": [0.1, 0.2]}]},
     r"sea\.toml: payload\[0\]\.mass_position: expected 3 numbers, got 2"),
    ({"payload": [{"time": 1.0, "damping_scale": [1, 1, 1]}]},
     r"sea\.toml: payload\[0\]\.damping_scale: expected 6 numbers or one number, got shape \(3,\)"),
]


@pytest.mark.parametrize(("tables", "message"), BAD, ids=[m for _, m in BAD])
def test_bad_sea_input_is_named_by_file_and_key(tables: dict, message: str) -> None:
    with pytest.raises(ScenarioError, match=message):
        scenario(**tables)


def test_bad_sea_input_in_a_file_names_the_file(tmp_path: Path) -> None:
    path = tmp_path / "rough.toml"
    text = (SCENARIO_DIR / "nerov_square.toml").read_text() + "\n[waves]\nhs = 2.0\ngamma = 0.5\n"
    path.write_text(text)
    with pytest.raises(ScenarioError, match=r"rough\.toml: waves\.gamma = 0\.5: expected >= 1"):
        read_scenario(path)


SEA_STATES = {2: (0.3, 7.5), 3: (0.88, 7.5), 4: (1.88, 8.8), 5: (3.25, 9.7)}


@pytest.mark.parametrize("vehicle", ["nerov", "bluerov2"])
@pytest.mark.parametrize("state", sorted(SEA_STATES))
def test_sea_state_scenarios_are_the_table_below_the_minimum_depth(vehicle: str, state: int) -> None:
    s = read_scenario(SCENARIO_DIR / f"{vehicle}_square_sea_state_{state}.toml")
    hs, tp = SEA_STATES[state]  # docs/disturbances.md, the sea-state table
    assert (s.waves.hs, s.waves.tp, s.waves.spectrum) == (hs, tp, _core.WaveSpectrum.jonswap)
    assert s.current_model == _core.CurrentModel.gauss_markov
    assert len(s.payload) == 1 and s.payload[0].mass > 0
    _, poses = s.command.timed_poses()
    # The whole path and the start are below 1.2 Hs plus a metre for the body.
    assert min(poses[:, 2].min(), s.eta0[2]) >= 1.2 * hs + 1.0


def test_sea_state_5_run_stays_below_the_minimum_depth() -> None:
    s = read_scenario(SCENARIO_DIR / "nerov_square_sea_state_5.toml")
    r = simulate(s.replace(duration=60.0))
    assert not r.diverged and not np.any(r.faults & 32)
    assert np.ptp(r.wave_elevation) > 3.0


def test_the_sea_example_uses_every_key_of_the_issue() -> None:
    path = ROOT / "examples" / "scenarios" / "sea_state_4_pickup.toml"
    data = tomllib.loads(path.read_text())
    assert {"model", "speed", "speed_std", "time_constant", "speed_min", "speed_max", "direction",
            "direction_std"} <= set(data["current"])
    assert {"spectrum", "hs", "tp", "gamma", "direction", "components"} <= set(data["waves"])
    assert {"time", "mass", "buoyancy"} <= set(data["payload"][0])
    s = read_scenario(path)
    assert s.current_model == _core.CurrentModel.gauss_markov and s.waves.hs == 1.88
    assert s.eta0[2] > 1.2 * s.waves.hs + 1.0


def test_a_computed_torque_controller_table_reads_and_names_a_bad_gain() -> None:
    # The sea_state study runs every controller of the registry; a computed
    # torque [controller] table is checked without its plant model (put in
    # from the scenario's vehicle when the controller is built).
    s = scenario(controller={"type": "computed_torque", "lambda": 0.5, "kd": [200, 200, 200, 50, 50, 50]})
    assert s.controller.type == "computed_torque" and s.controller.config.vehicle is None
    np.testing.assert_array_equal(s.controller.config.kd, [200, 200, 200, 50, 50, 50])
    r = simulate(s.replace(duration=20.0))
    assert not r.diverged and r.metrics()["rmse_position_m"] < 0.5
    with pytest.raises(ScenarioError, match=r"sea\.toml: controller\.kd\[2\] = -1: expected >= 0"):
        scenario(controller={"type": "computed_torque", "kd": [1, 1, -1, 1, 1, 1]})


def _gm_study(tmp_path: Path, perturbation: str):
    from neurov.study import load_study

    path = tmp_path / "gm.toml"
    path.write_text(f'''name = "gm"
seed = 3
samples = 2
scenarios = ["nerov_square_sea_state_2"]
[[perturbations]]
{perturbation}
[[perturbations]]
parameter = "current_direction"
range = [0.0, 360.0]
[controllers.pd]
type = "pd"
kp = [100, 100, 100, 25, 25, 25]
kd = [200, 200, 200, 50, 50, 50]
''')
    return load_study(path)


def test_a_study_moves_the_mean_of_a_gauss_markov_current(tmp_path: Path) -> None:
    from neurov.study import sample_plant

    study = _gm_study(tmp_path, 'parameter = "current_speed"\nrange = [0.1, 0.6]')
    base = study.scenarios[0]
    for k in range(2):
        plant, cols = sample_plant(study, base, k)
        gm = plant.gauss_markov_current
        assert (gm.speed, gm.direction) == (cols["p_current_speed"], cols["p_current_direction"])
        assert (gm.speed_std, gm.time_constant) == (base.gauss_markov_current.speed_std, 30.0)
        assert not np.any(plant.current)
        assert not simulate(plant.replace(duration=20.0)).diverged
    assert base.gauss_markov_current.speed == 0.3  # the study's scenario is left as it was


def test_a_study_refuses_a_current_speed_outside_the_gauss_markov_bounds(tmp_path: Path) -> None:
    from neurov.study import StudyError

    with pytest.raises(StudyError, match=r"gm\.toml: perturbations: current_speed from 0\.1 to 1\.5 m/s: scenario "
                                         r"'nerov_square_sea_state_2' has a Gauss-Markov current.*\[0, 1\]"):
        _gm_study(tmp_path, 'parameter = "current_speed"\nrange = [0.1, 1.5]')
