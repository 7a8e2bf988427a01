"""Studies: study files, perturbed plants, the same table from Dask and from
local processes, resuming, and the league table."""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

from neurov import cli
from neurov.scenario import load_scenario
from neurov.simulation import build_controller
from neurov.study import (
    LOG_NAME,
    SCENARIO_DIR,
    StudyError,
    draw_sample,
    failed,
    league_markdown,
    load_study,
    percentile,
    read_table,
    run_study,
    sample_plant,
    shipped_studies,
    study_from_mapping,
    summarise,
)
from neurov.vehicle_file import load_vehicle_parameters, preset_path


# A short BlueROV2 heading step next to a shipped scenario trimmed to 30 s,
# so the whole file runs in seconds.
SHORT_BLUEROV = """
name = "short_bluerov"
duration = 30.0
[vehicle]
preset = "bluerov2_heavy"
[command]
type = "waypoints"
interpolation = "hold"
times = [0.0, 2.0]
poses = [[0, 0, 1, 0, 0, 0], [1, 0, 1, 0, 0, 0.5]]
[controller]
type = "pd"
kp = 10.0
kd = 10.0
[current]
velocity = [0.2, 0.0, 0.0]
[noise]
eta = [0.01, 0.01, 0.01, 0.002, 0.002, 0.005]
"""

SHORT_NEROV = """
name = "short_nerov"
duration = 30.0
[vehicle]
preset = "nerov"
thrusters = true
[command]
type = "waypoints"
interpolation = "hold"
times = [0.0, 2.0]
poses = [[0, 0, 0, 0, 0, 0], [0, 0, 2, 0, 0, 0.5]]
[controller]
type = "pd"
kp = 50.0
kd = 200.0
[[disturbances]]
dof = "yaw"
amplitude = 10.0
frequency = 0.05
"""

STUDY = """
name = "small"
description = "2 scenarios x 3 controllers x 4 samples"
seed = 7
samples = 4
after = 5.0
scenarios = ["short_nerov.toml", "short_bluerov.toml"]
head_to_head = [["nn", "linear"]]

[ranking]
metric = "rmse_position_m"

[failure]
rmse_position_m = 0.5

[controllers.pd]
type = "pd"
label = "PD"
[controllers.pd.nerov]
kp = [100, 100, 100, 50, 50, 50]
kd = [200, 200, 200, 50, 50, 50]
[controllers.pd.bluerov2_heavy]
kp = [20, 20, 20, 2, 2, 2]
kd = [25, 25, 40, 1, 1, 1]

[controllers.linear]
type = "linear"
theta0 = "true"
label = "linear adaptive"
[controllers.linear.nerov]
kd = [200, 200, 200, 50, 50, 50]
[controllers.linear.bluerov2_heavy]
kd = [25, 25, 40, 1, 1, 1]
gamma = 0.1

[controllers.nn]
type = "nn"
label = "NN adaptive"
[controllers.nn.centres]
method = "sobol"
n = 16
seed = 1
[controllers.nn.nerov]
kd = [200, 200, 200, 50, 50, 50]
[controllers.nn.bluerov2_heavy]
kd = [25, 25, 40, 1, 1, 1]
gamma = 0.03

[[perturbations]]
parameter = "mass"
relative = 0.3

[[perturbations]]
parameter = "added_mass"
relative = 0.2
distribution = "normal"

[[perturbations]]
parameter = "linear_damping"
relative = 0.3
per_element = false

[[perturbations]]
parameter = "current_speed"
range = [0.0, 0.5]

[[perturbations]]
parameter = "current_direction"
range = [0.0, 360.0]

[[perturbations]]
parameter = "noise_scale"
range = [0.5, 2.0]
"""


def write_study(folder: Path, text: str = STUDY, name: str = "small.toml") -> Path:
    (folder / "short_nerov.toml").write_text(SHORT_NEROV)
    (folder / "short_bluerov.toml").write_text(SHORT_BLUEROV)
    path = folder / name
    path.write_text(text)
    return path


@pytest.fixture
def study_file(tmp_path: Path) -> Path:
    return write_study(tmp_path)


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


def _study_with(change: str) -> str:
    """The small study with one top-level key or table replaced by `change`."""
    base = [
        'name = "small"', "seed = 1", "samples = 2",
        'scenarios = ["short_nerov.toml", "short_bluerov.toml"]',
        "[controllers.pd]", 'type = "pd"', "kp = 1.0", "kd = 1.0",
    ]
    head, _, _ = change.partition("\n")
    key = head.split("=")[0].strip()
    if key.startswith("[controllers"):
        base = base[:4] + [change]
    elif "=" in head and not head.startswith("["):
        base = [line for line in base if not line.startswith(key + " ")]
        base.insert(0, change)
    else:
        base.append(change)
    return "\n".join(base) + "\n"


@pytest.mark.parametrize(("change", "message"), BAD)
def test_bad_study_file_names_the_file_and_field(tmp_path: Path, change: str, message: str) -> None:
    path = write_study(tmp_path, _study_with(change))
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


# --- running -------------------------------------------------------------------------


def test_dask_and_local_processes_give_identical_tables(study_file: Path, tmp_path: Path) -> None:
    pytest.importorskip("dask.distributed")
    a = run_study(study_file, tmp_path / "dask", executor="dask", workers=2, dask_processes=False,
                  progress=False, plots=False)
    b = run_study(study_file, tmp_path / "procs", executor="processes", workers=2, progress=False,
                  plots=True)
    assert a.executor == "dask" and b.executor == "processes"
    assert a.total == b.total == 2 * 3 * 4 and a.ran == b.ran == 24
    assert a.table_path.read_bytes() == b.table_path.read_bytes()
    assert a.league.read_text() == b.league.read_text()
    pd.testing.assert_frame_equal(read_table(b.table_path), b.table)
    rows = b.table.to_dict("records")
    assert len(rows) == 24
    assert [(r["scenario"], r["controller"], r["sample"]) for r in rows[:5]] == [
        ("short_nerov", "pd", 0), ("short_nerov", "pd", 1), ("short_nerov", "pd", 2),
        ("short_nerov", "pd", 3), ("short_nerov", "linear", 0)]
    assert {"rmse_position_m", "rmse_yaw", "p_mass", "p_added_mass_5", "failed", "noise_seed"} <= set(rows[0])
    assert all(math.isfinite(r["rmse_position_m"]) for r in rows)
    for name in ("boxplot_rmse_position_m.png", "error_bands_short_nerov.png", "error_bands_short_bluerov.png"):
        assert (tmp_path / "procs" / name).stat().st_size > 10_000
    timing = json.loads((tmp_path / "procs" / "timing.json").read_text())
    assert timing["runs"] == 24 and timing["runs_per_second"] > 0


def test_resume_skips_finished_runs_and_gives_the_same_table(study_file: Path, tmp_path: Path) -> None:
    out = tmp_path / "out"
    first = run_study(study_file, out, executor="processes", workers=1, progress=False, plots=False)
    table = first.table_path.read_bytes()
    again = run_study(study_file, out, executor="processes", workers=1, progress=False, plots=False)
    assert again.ran == 0 and again.skipped == 24
    assert again.table_path.read_bytes() == table
    # Lose five runs, and cut the last line short as an interrupted write would.
    lines = (out / LOG_NAME).read_text().splitlines(keepends=True)
    kept = lines[:18] + [lines[18][:40]]
    (out / LOG_NAME).write_text("".join(kept))
    resumed = run_study(study_file, out, executor="processes", workers=1, progress=False, plots=False)
    assert resumed.ran == 6 and resumed.skipped == 18
    assert resumed.table_path.read_bytes() == table


def test_more_samples_reuse_the_runs_already_made(tmp_path: Path) -> None:
    two = write_study(tmp_path, STUDY.replace("samples = 4", "samples = 2"), "two.toml")
    four = write_study(tmp_path, STUDY, "four.toml")
    out = tmp_path / "out"
    run_study(two, out, executor="processes", workers=1, progress=False, plots=False)
    more = run_study(four, out, executor="processes", workers=1, progress=False, plots=False)
    assert more.ran == 12 and more.skipped == 12
    fresh = run_study(four, tmp_path / "fresh", executor="processes", workers=1, progress=False, plots=False)
    assert more.table_path.read_bytes() == fresh.table_path.read_bytes()


def test_a_different_study_in_the_same_folder_is_refused(tmp_path: Path) -> None:
    out = tmp_path / "out"
    small = STUDY.replace("samples = 4", "samples = 1")
    run_study(write_study(tmp_path, small, "a.toml"), out, executor="processes", workers=1,
              progress=False, plots=False)
    other = write_study(tmp_path, small.replace("seed = 7", "seed = 8"), "b.toml")
    with pytest.raises(StudyError, match="holds runs of a different study"):
        run_study(other, out, executor="processes", workers=1, progress=False, plots=False)
    # Judging differently is not a different study: no run is redone.
    judged = write_study(tmp_path, small.replace("rmse_position_m = 0.5", "rmse_position_m = 0.01"), "c.toml")
    outcome = run_study(judged, out, executor="processes", workers=1, progress=False, plots=False)
    assert outcome.ran == 0
    table = read_table(outcome.table_path)
    assert (table.loc[table["rmse_position_m"] > 0.01, "failed"] == 1).all()


# --- summaries -------------------------------------------------------------------------


def test_percentile_handles_inf() -> None:
    assert percentile([1.0, 2.0, 3.0], 50) == 2.0
    assert percentile([1.0, 2.0, 3.0, 4.0], 5) == pytest.approx(np.percentile([1, 2, 3, 4], 5))
    assert percentile([1.0, float("nan"), float("inf")], 50) == float("inf")
    assert percentile([1.0, 2.0, float("inf")], 50) == 2.0
    assert percentile([1.0, 2.0, float("inf")], 95) == float("inf")


def test_failure_is_a_stated_bound_or_a_non_finite_value() -> None:
    row = {"rmse_position_m": 0.2, "rmse_yaw_rad": 0.1, "diverged": 0.0, "max_position_error_m": 1.0}
    assert not failed(row, {"rmse_position_m": 0.5})
    assert failed(row, {"rmse_position_m": 0.1})
    assert failed(row | {"rmse_yaw_rad": float("nan")}, {})
    assert failed(row | {"diverged": 1.0}, {})
    assert failed(row | {"max_position_error_m": float("inf")}, {"max_position_error_m": 5.0})


def test_league_table_ranks_by_the_median(study_file: Path) -> None:
    s = load_study(study_file)
    s.failure = {"rmse_position_m": 5.0}
    rows = []
    values = {"pd": [3.0, 3.0, 3.0, 3.0], "linear": [1.0, 2.0, 2.0, 9.0], "nn": [1.0, 1.0, 1.0, float("inf")]}
    for sc in s.scenarios:
        for c, vals in values.items():
            for k, v in enumerate(vals):
                rows.append({"scenario": sc.name, "controller": c, "sample": k, "rmse_position_m": v,
                             "rmse_yaw_rad": 0.0, "diverged": 0.0})
    summ = summarise(s, rows)
    first = [g for g in summ if g.scenario == "short_nerov"]
    assert [g.controller for g in first] == ["nn", "linear", "pd"]
    assert first[0].median == 1.0 and first[0].failure_rate == 0.25  # inf: not finite
    assert first[1].median == 2.0 and first[1].failure_rate == 0.25  # 9 > the bound of 5
    assert first[2].failure_rate == 0.0
    md = league_markdown(s, rows)
    assert "| 1 | NN adaptive | 1 |" in md
    s.also_show = ["rmse_yaw_rad"]
    assert "| median rmse_yaw_rad |" in league_markdown(s, rows)
    assert "## NN adaptive against linear adaptive" in md
    assert "| short_nerov | 2 of 4 |" in md  # nn < linear in samples 1 and 2 only


# --- command line ------------------------------------------------------------------------


def test_cli_study_writes_the_outputs(study_file: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    small = write_study(tmp_path, STUDY.replace("samples = 4", "samples = 1"), "one.toml")
    out = tmp_path / "cli"
    assert cli.main(["study", str(small), "--out", str(out), "--workers", "1", "--executor", "processes",
                     "--no-plots"]) == 0
    text = capsys.readouterr().out
    assert "6 runs (0 already done, 6 run in" in text
    assert "on 1 local process," in text and "worker(s)" not in text
    for name in ("runs.csv", "summary.csv", "league.md", "study.json", "timing.json", LOG_NAME):
        assert (out / name).exists()
    assert cli.main(["study", str(small), "--out", str(out), "--workers", "1", "--executor", "processes",
                     "--no-plots"]) == 0
    assert "6 already done, 0 run" in capsys.readouterr().out


def test_cli_study_error_names_the_field(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    path = write_study(tmp_path, _study_with("[ranking]\nmetric = \"speed\""))
    assert cli.main(["study", str(path), "--out", str(tmp_path / "o")]) == 1
    err = capsys.readouterr().err
    assert "ranking.metric: unknown metric 'speed'" in err and str(path) in err


def test_parquet_table_reads_back_as_the_csv_rows(tmp_path: Path) -> None:
    pytest.importorskip("pyarrow")
    small = write_study(tmp_path, STUDY.replace("samples = 4", "samples = 1"), "one.toml")
    a = run_study(small, tmp_path / "csv", executor="processes", workers=1, progress=False, plots=False)
    b = run_study(small, tmp_path / "pq", executor="processes", workers=1, progress=False, plots=False,
                  table_format="parquet")
    assert b.table_path.suffix == ".parquet"
    pd.testing.assert_frame_equal(read_table(a.table_path), read_table(b.table_path))


def test_a_folder_named_like_a_shipped_study_does_not_hide_it(tmp_path: Path,
                                                               monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.chdir(tmp_path)
    (tmp_path / "league").mkdir()  # e.g. the output of `neurov study league --out league`
    assert load_study("league").name == "league"


# --- crashes, interrupts and reruns ---------------------------------------------------------


def test_a_log_cut_by_a_crash_is_repaired_before_appending(tmp_path: Path) -> None:
    small = write_study(tmp_path, STUDY.replace("samples = 4", "samples = 1"), "one.toml")
    out = tmp_path / "out"
    first = run_study(small, out, executor="processes", workers=1, progress=False, plots=False)
    log = out / LOG_NAME
    lines = log.read_text().splitlines(keepends=True)
    # The crash: the last record half written, no newline.
    log.write_text("".join(lines[:-1]) + lines[-1][:50])
    resumed = run_study(small, out, executor="processes", workers=1, progress=False, plots=False)
    assert resumed.ran == 1
    # The broken line is gone and the finished run is on a line of its own.
    after = log.read_text().splitlines()
    assert len(after) == len(lines) and all(json.loads(line)["row"] for line in after)
    again = run_study(small, out, executor="processes", workers=1, progress=False, plots=False)
    assert again.ran == 0 and again.table_path.read_bytes() == first.table_path.read_bytes()


def test_repair_tail_keeps_complete_lines(tmp_path: Path) -> None:
    from neurov.study.log import repair_tail

    log = tmp_path / "log.jsonl"
    assert repair_tail(log) == 0  # no file yet
    log.write_bytes(b'{"a": 1}\n{"b": 2}\n')
    assert repair_tail(log) == 0 and log.read_bytes() == b'{"a": 1}\n{"b": 2}\n'
    log.write_bytes(b'{"a": 1}\n{"b": 2}\n{"c": ')
    assert repair_tail(log) == 6 and log.read_bytes() == b'{"a": 1}\n{"b": 2}\n'
    log.write_bytes(b"x" * 100_000)  # one broken line, longer than a read block
    assert repair_tail(log) == 100_000 and log.read_bytes() == b""


def test_ctrl_c_says_what_is_saved_and_exits_130(tmp_path: Path, monkeypatch: pytest.MonkeyPatch,
                                                 capsys: pytest.CaptureFixture[str]) -> None:
    import neurov.study.running as running

    small = write_study(tmp_path, STUDY.replace("samples = 4", "samples = 1"), "one.toml")
    out = tmp_path / "out"
    real = running.run_batch
    calls = []

    def interrupted_on_the_third(study: object, keys: object) -> object:
        calls.append(keys)
        if len(calls) == 3:
            raise KeyboardInterrupt
        return real(study, keys)  # type: ignore[arg-type]

    monkeypatch.setattr(running, "run_batch", interrupted_on_the_third)
    args = ["study", str(small), "--out", str(out), "--workers", "1", "--executor", "processes",
            "--no-plots", "--batch-size", "1"]
    assert cli.main(args) == 130
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "Traceback" not in err
    assert f"2 of 6 runs are saved in {out / LOG_NAME}" in err and "again to resume" in err
    monkeypatch.setattr(running, "run_batch", real)
    assert cli.main(args) == 0
    assert "6 runs (2 already done, 4 run in" in capsys.readouterr().out


@pytest.mark.parametrize("executor", ["processes", "dask"])
def test_ctrl_c_from_the_terminal_stops_worker_processes_quietly(tmp_path: Path, executor: str) -> None:
    if executor == "dask":
        pytest.importorskip("dask.distributed")
    import os
    import signal
    import subprocess
    import sys
    import time

    many = write_study(tmp_path, STUDY.replace("samples = 4", "samples = 100"), "many.toml")
    out = tmp_path / "out"
    proc = subprocess.Popen([sys.executable, "-m", "neurov.cli", "study", str(many), "--out", str(out),
                             "--workers", "2", "--executor", executor, "--no-plots"],
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                            start_new_session=True)
    log = out / LOG_NAME
    deadline = time.monotonic() + 120
    while not (log.exists() and log.stat().st_size > 0) and time.monotonic() < deadline:
        time.sleep(0.05)
    assert proc.poll() is None, "the study finished before it could be interrupted"
    # As the terminal does: SIGINT to the whole process group, workers included.
    os.killpg(proc.pid, signal.SIGINT)
    _, err = proc.communicate(timeout=120)
    assert proc.returncode == 130, err
    assert "Traceback" not in err and err.count("\n") == 1, err
    saved = len(log.read_text().splitlines())
    assert f"{saved} of 600 runs are saved" in err


def test_plots_are_redrawn_only_when_their_data_changed(tmp_path: Path) -> None:
    one = write_study(tmp_path, STUDY.replace("samples = 4", "samples = 1"), "one.toml")
    two = write_study(tmp_path, STUDY.replace("samples = 4", "samples = 2"), "two.toml")
    out = tmp_path / "out"
    run_study(one, out, executor="processes", workers=1, progress=False)
    figures = ["boxplot_rmse_position_m.png", "error_bands_short_nerov.png", "error_bands_short_bluerov.png"]
    stamps = {f: (out / f).stat().st_mtime_ns for f in figures}
    assert json.loads((out / "timing.json").read_text())["figures_drawn"] == 3
    run_study(one, out, executor="processes", workers=1, progress=False)
    assert json.loads((out / "timing.json").read_text())["figures_drawn"] == 0
    assert {f: (out / f).stat().st_mtime_ns for f in figures} == stamps
    (out / figures[1]).unlink()  # a missing figure is drawn again, alone
    run_study(one, out, executor="processes", workers=1, progress=False)
    assert json.loads((out / "timing.json").read_text())["figures_drawn"] == 1
    run_study(two, out, executor="processes", workers=1, progress=False)  # new runs: all redrawn
    assert json.loads((out / "timing.json").read_text())["figures_drawn"] == 3
