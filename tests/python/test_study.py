"""Studies: study files (shipped and bad ones), the perturbed plant of each
sample, and the failure and ranking rules."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from neurov.config.reading import load_scenario
from neurov.laws.registry import build_controller
from neurov.study import (
    SCENARIO_DIR,
    StudyError,
    draw_sample,
    load_study,
    sample_plant,
    shipped_studies,
)
from neurov.config.vehicle_file import load_vehicle_parameters, preset_path

from study_files import study_file, study_with, write_study  # noqa: F401  (study_file: a fixture)


# --- loading ---------------------------------------------------------------------


def test_study_file_loads_with_per_vehicle_gains(study_file: Path) -> None:
    s = load_study(study_file)
    assert [sc.name for sc in s.scenarios] == ["short_nerov", "short_bluerov"]
    assert s.controllers == ["pd", "linear", "nn"]
    assert s.spec_for("pd", s.scenarios[1]).kp[0] == 20
    assert s.spec_for("pd", s.scenarios[0]).kp[0] == 100
    nn_blue = s.spec_for("nn", s.scenarios[1])
    assert nn_blue.gamma == 0.03 and nn_blue.centres["n"] == 16
    assert s.spec_for("nn", s.scenarios[0]).gamma == 0.3  # the default where not given
    assert s.label("nn") == "NN adaptive"


def test_shipped_studies_load() -> None:
    assert {"league", "robustness"} <= set(shipped_studies())
    for name in shipped_studies():
        s = load_study(name)
        assert s.scenarios and s.controllers


def test_shipped_scenarios_load_and_pair_calm_with_disturbed() -> None:
    names = sorted(p.stem for p in SCENARIO_DIR.glob("*.toml"))
    for vehicle in ("nerov", "bluerov2"):
        for path in ("square", "helix", "lawnmower", "depth_step", "heading_step"):
            calm = load_scenario(SCENARIO_DIR / f"{vehicle}_{path}.toml")
            rough = load_scenario(SCENARIO_DIR / f"{vehicle}_{path}_disturbed.toml")
            assert not calm.disturbances and not np.any(calm.current) and not np.any(calm.noise_eta)
            assert rough.disturbances[0].dof == 5
            assert np.hypot(*rough.current[:2]) == pytest.approx(0.5)
            assert np.all(rough.noise_eta > 0)
            assert calm.command.type == rough.command.type
    assert "paper_fig3" in names


def test_helix_is_eight_metres_one_turn_five_metres_down_in_150_s() -> None:
    s = load_scenario(SCENARIO_DIR / "nerov_helix.toml")
    t, poses = s.command.timed_poses()
    assert t[-1] - t[0] == pytest.approx(150.0)
    assert poses[-1, 2] - poses[0, 2] == pytest.approx(5.0)
    radius = np.hypot(poses[:, 0], poses[:, 1] - 8.0)
    np.testing.assert_allclose(radius, 8.0, atol=1e-9)


BAD = [
    ("scenarios = 3", r"small\.toml: scenarios: expected a non-empty list"),
    ('scenarios = ["short_nerov.toml", "nerov_sqare"]', r"scenarios\[1\]: no scenario 'nerov_sqare'.*did you mean 'nerov_square'"),
    ("[controllers.pd]\ntype = \"pdd\"", r"controllers\.pd\.type: expected one of"),
    ("[controllers.pd]\ntype = \"pd\"\n[controllers.pd.nerov]\nkp = 1.0\nkd = -1.0\n"
     "[controllers.pd.bluerov2_heavy]\nkp = 1.0", r"controllers\.pd\.nerov\.kd\[0\] = -1: expected >= 0"),
    ("[controllers.pd]\ntype = \"pd\"\n[controllers.pd.nerov]\nkp = 1.0\n[controllers.pd.bluerov2]\nkp = 1.0",
     r"controllers\.pd\.bluerov2: no scenario of this study uses a vehicle 'bluerov2'.*did you mean 'bluerov2_heavy'"),
    ("[controllers.pd]\ntype = \"pd\"\n[controllers.pd.nerov]\nkp = 1.0",
     r"controllers\.pd: gives gains for \['nerov'\] but not for vehicle 'bluerov2_heavy'"),
    ("[[perturbations]]\nparameter = \"mas\"\nrelative = 0.1", r"perturbations\[0\]\.parameter: .*did you mean 'mass'"),
    ("[[perturbations]]\nparameter = \"mass\"\nrelative = 1.5", r"perturbations\[0\]\.relative: expected a number < 1"),
    ("[[perturbations]]\nparameter = \"mass\"\nrelative = 0.6\ndistribution = \"normal\"",
     r"perturbations\[0\]\.relative: expected a number < 0.5"),
    ("[[perturbations]]\nparameter = \"current_speed\"\nrange = [0.5, 0.1]", r"perturbations\[0\]\.range: expected \[low, high\]"),
    ("[[perturbations]]\nparameter = \"current_speed\"\nmean = 0.1\nstd = 0.2\ndistribution = \"normal\"",
     r"perturbations\[0\]\.std: current_speed must stay >= 0"),
    ("[[perturbations]]\nparameter = \"mass\"\nrelative = 0.1\nper_element = true", r"perturbations\[0\]\.per_element"),
    ("[ranking]\nmetric = \"rmse_positon_m\"", r"ranking\.metric: unknown metric 'rmse_positon_m'; did you mean 'rmse_position_m'"),
    ("[failure]\nrmse_position_m = \"big\"", r"failure\.rmse_position_m: expected a number"),
    ("[ranking]\nalso_show = [\"rmse_yw_rad\"]", r"ranking\.also_show\[0\]: unknown metric 'rmse_yw_rad'"),
    ("[controllers.pd]\ntype = \"nn\"\nmodification = \"sigma\"", r"controllers\.pd\.sigma_m = 0: expected > 0"),
    ("[controllers.pd]\ntype = \"nn\"\nkd = 1.0\n[controllers.pd.centres]\nmethod = \"sobol\"\nn = 4\n"
     "[controllers.pd.nerov]\nmodification = \"projection\"\n[controllers.pd.bluerov2_heavy]\ngamma = 0.1",
     r"controllers\.pd\.w_max = 0: expected > 0"),
    ("samples = 0", r"samples: expected an integer >= 1"),
    ("sampels = 3", r"sampels: unknown field; did you mean 'samples'"),
    ("after = 100.0", r"after: 100.0 s leaves no samples of scenario 'short_nerov'"),
    ("head_to_head = [[\"nn\", \"pid\"]]", r"head_to_head\[0\]: expected two of"),
]


@pytest.mark.parametrize(("change", "message"), BAD)
def test_bad_study_file_names_the_file_and_field(tmp_path: Path, change: str, message: str) -> None:
    path = write_study(tmp_path, study_with(change))
    with pytest.raises(StudyError, match=message) as info:
        load_study(path)
    assert str(path) in str(info.value)


def test_unknown_study_name_and_bad_toml(tmp_path: Path) -> None:
    with pytest.raises(StudyError, match="no shipped study of that name"):
        load_study("robustnes")
    bad = tmp_path / "bad.toml"
    bad.write_text("samples = [")
    with pytest.raises(StudyError, match=r"bad\.toml: not valid TOML"):
        load_study(bad)


def test_perturbations_that_break_the_vehicle_are_refused(tmp_path: Path) -> None:
    # With the centre of gravity 0.1 m below the origin, M stays positive
    # definite only while I + added inertia > m z_g^2 (here 0.11 > 0.10): a
    # heavier plant at the top of the range is not a vehicle.
    vehicle = tmp_path / "pendulum.toml"
    vehicle.write_text(
        "mass = 10.0\ninertia = [0.11, 0.11, 0.11]\ncentre_of_gravity = [0, 0, 0.1]\n"
        "weight = 98.1\nbuoyancy = 98.1\nadded_mass = [0, 0, 0, 0, 0, 0]\n"
        "linear_damping = [10, 10, 10, 1, 1, 1]\nquadratic_damping = [0, 0, 0, 0, 0, 0]\n")
    (tmp_path / "pendulum_scenario.toml").write_text(
        "duration = 10.0\n[vehicle]\nfile = \"pendulum.toml\"\n"
        "[command]\ntype = \"waypoints\"\ntimes = [0.0]\nposes = [[0, 0, 0, 0, 0, 0]]\n"
        "[controller]\ntype = \"pd\"\nkp = 1.0\nkd = 1.0\n")
    text = ('scenarios = ["pendulum_scenario.toml"]\n[controllers.pd]\ntype = "pd"\nkp = 1.0\n'
            '[[perturbations]]\nparameter = "mass"\nrelative = 0.05\n')
    (tmp_path / "ok.toml").write_text(text)
    load_study(tmp_path / "ok.toml")
    (tmp_path / "heavy.toml").write_text(text.replace("0.05", "0.3"))
    with pytest.raises(StudyError, match=r"heavy\.toml: perturbations: scenario 'pendulum_scenario': at the "
                       r"extreme factors \(high\) the vehicle is not valid"):
        load_study(tmp_path / "heavy.toml")


# --- plants ------------------------------------------------------------------------


def test_each_sample_has_its_own_plant_fixed_by_seed_and_index(study_file: Path) -> None:
    s = load_study(study_file)
    nominal = load_vehicle_parameters(preset_path("nerov"))
    plants = [sample_plant(s, s.scenarios[0], k) for k in range(4)]
    again = [sample_plant(s, s.scenarios[0], k) for k in (3, 2, 1, 0)][::-1]
    for (a, ca), (b, cb) in zip(plants, again):
        assert ca == cb and a.seed == b.seed
        assert a.vehicle_parameters == b.vehicle_parameters
    seeds = {p.seed for p, _ in plants}
    assert len(seeds) == 4
    for plant, cols in plants:
        v = plant.vehicle_parameters
        assert 0.7 <= v["mass"] / nominal["mass"] <= 1.3
        assert v["mass"] / nominal["mass"] == pytest.approx(cols["p_mass"])
        f = np.array(v["added_mass"]) / np.array(nominal["added_mass"])
        assert np.all((f >= 0.6) & (f <= 1.4))
        np.testing.assert_allclose(f, [cols[f"p_added_mass_{i}"] for i in range(6)])
        # One factor for the whole linear damping vector (per_element = false).
        g = np.array(v["linear_damping"]) / np.array(nominal["linear_damping"])
        np.testing.assert_allclose(g, g[0])
        assert np.hypot(*plant.current[:2]) == pytest.approx(cols["p_current_speed"])
        assert math.degrees(math.atan2(plant.current[1], plant.current[0])) % 360 == pytest.approx(
            cols["p_current_direction"] % 360)
        # The nominal scenario has no noise, so its scale leaves none.
        assert not np.any(plant.noise_eta)
        # Weight and buoyancy stay as in the file: mass is an inertia error.
        assert v["weight"] == nominal["weight"]
    # The same draws meet the other vehicle (common random numbers).
    blue, cols_blue = sample_plant(s, s.scenarios[1], 2)
    assert cols_blue == plants[2][1]
    np.testing.assert_allclose(blue.noise_eta, s.scenarios[1].noise_eta * cols_blue["p_noise_scale"])


def test_the_controller_is_designed_for_the_nominal_vehicle(study_file: Path) -> None:
    from neurov import _core

    s = load_study(study_file)
    plant, _ = sample_plant(s, s.scenarios[0], 1)
    spec = s.spec_for("linear", s.scenarios[0])
    nominal = _core.regressor_parameters(_core.Vehicle(**load_vehicle_parameters(preset_path("nerov"))))
    perturbed = _core.regressor_parameters(_core.Vehicle(**plant.vehicle_parameters))
    assert not np.allclose(nominal, perturbed)
    np.testing.assert_array_equal(build_controller(spec, plant).theta, nominal)


def test_normal_draws_stay_within_two_standard_deviations(study_file: Path) -> None:
    s = load_study(study_file)
    f = np.array([draw_sample(s, k)[0]["added_mass"] for k in range(300)])
    assert f.min() >= 1 - 2 * 0.2 and f.max() <= 1 + 2 * 0.2
    assert abs(f.std() - 0.2 * 0.88) < 0.02  # the sd of a normal truncated at 2
