"""A study naming a user's controller by import path runs it on every scenario
and perturbed plant, on local processes and on Dask workers, and ranks it
beside the built-ins; a factory that cannot run is named before any run."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from neurov.results.metrics import metric_names
from neurov.study import StudyError, load_study, run_study
from study_files import MASS_PERTURBATION, NOISE, pd_study, step_scenario


STUDY = pd_study("byoc", seed=3, samples=3, after=5.0) + """
[controllers.mine]
{mine}
""" + MASS_PERTURBATION + """
[[perturbations]]
parameter = "current_speed"
range = [0.0, 0.3]
"""

PYTHON_PD = 'factory = "user_controllers.factories:python_pd"\nlabel = "my PD"'


def write(folder: Path, mine: str = PYTHON_PD) -> Path:
    for name, x in (("a", 1), ("b", -2)):
        (folder / f"{name}.toml").write_text(step_scenario(
            name, "nerov", [0, 0, 0, 0, 0, 0], [x, 0, 2, 0, 0, 0.5], kp=50.0, kd=200.0,
            duration=20.0, thrusters=True, extra=NOISE))
    path = folder / "study.toml"
    path.write_text(STUDY.format(mine=mine))
    return path


pytestmark = pytest.mark.usefixtures("user_controllers_importable")


@pytest.mark.parametrize("executor", ["processes", "dask"])
def test_a_factory_controller_runs_everywhere_and_ranks_beside_the_built_ins(tmp_path: Path,
                                                                          executor: str) -> None:
    if executor == "dask":
        pytest.importorskip("dask.distributed")
    out = run_study(write(tmp_path), tmp_path / executor, executor=executor, workers=2, progress=False,
                    plots=False, **({"dask_processes": True} if executor == "dask" else {}))
    assert out.total == out.ran == 2 * 2 * 3
    rows = out.table
    mine = rows[rows.controller == "mine"].reset_index(drop=True)
    pd_rows = rows[rows.controller == "pd"].reset_index(drop=True)
    assert len(mine) == len(pd_rows) == 6
    # The same law stepped from Python: the same run on every plant.
    for column in ("sample", "noise_seed", "p_mass", "p_current_speed", *metric_names()):
        np.testing.assert_allclose(mine[column].to_numpy(dtype=float), pd_rows[column].to_numpy(dtype=float),
                                   rtol=1e-9, err_msg=column)
    assert list(mine.scenario) == list(pd_rows.scenario) == ["a"] * 3 + ["b"] * 3
    assert len(set(mine.p_mass)) == 3  # each sample its own plant
    league = out.league.read_text()
    assert "my PD" in league and "| pd |" in league.replace("| PD |", "| pd |")


@pytest.mark.parametrize(
    ("mine", "message"),
    [
        ('factory = "no_such_module_xyz:make"', "cannot import module 'no_such_module_xyz'"),
        ('factory = "user_controllers.factories:missing"', "has no 'missing'"),
        ('factory = "user_controllers.factories:NOT_CALLABLE"', "'NOT_CALLABLE' is a int, not a function"),
        ('factory = "user_controllers.factories:not_a_controller"', "returned a int .* no method step"),
        ('factory = "user_controllers.factories:raises"', "raised RuntimeError for scenario 'a': no gains"),
        ('factory = "user_controllers.factories"', "expected 'module.path:function'"),
        ('factory = "user_controllers.factories:python_pd"\nkp = 3.0', r"\.kp: a controller given by a factory takes only"),
    ],
)
def test_a_factory_that_cannot_run_is_named_before_any_run(tmp_path: Path, mine: str, message: str) -> None:
    path = write(tmp_path, mine)
    with pytest.raises(StudyError, match=rf"study.toml: controllers.mine.*{message}"):
        load_study(path)
    with pytest.raises(StudyError, match=message):
        run_study(path, tmp_path / "out", executor="processes", workers=1, progress=False, plots=False)
    assert not (tmp_path / "out" / "runs.csv").exists()


def test_the_fingerprint_follows_the_factory_path(tmp_path: Path) -> None:
    a = load_study(write(tmp_path))
    b = load_study(write(tmp_path, PYTHON_PD.replace("my PD", "other label")))
    assert a.fingerprint() == b.fingerprint()
    assert a.label("mine") == "my PD" and a.label("pd") == "pd"
