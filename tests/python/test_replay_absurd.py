"""A result whose values are finite but absurd (1e300) no longer sets the
replay's scale without a word: those values are passed over as non-finite
ones are, and ``neurov view`` and :func:`build_scene` say which. Before,
one pose at 1e300 m made the scene 2e300 m wide and the run a point."""

from __future__ import annotations

import dataclasses
from pathlib import Path

import numpy as np
import pytest

import neurov
from neurov.cli import main
from neurov.replay.scene import AbsurdValuesWarning, MAX_POSITION_M, build_scene
from neurov.study.spec import SCENARIO_DIR


@pytest.fixture(scope="module")
def run() -> neurov.Result:
    return neurov.simulate(neurov.load_scenario(SCENARIO_DIR / "bluerov2_depth_step.toml").replace(duration=2.0))


def _absurd(run: neurov.Result, name: str) -> neurov.Result:
    values = getattr(run, name).copy()
    values[3:, 0] = 1e300
    return dataclasses.replace(run, **{name: values})


@pytest.mark.parametrize(("name", "unit"), [("eta", "m"), ("thrusts", "N"), ("current", "m/s")])
def test_absurd_values_are_passed_over_and_said(run: neurov.Result, name: str, unit: str) -> None:
    plain = build_scene([run], ["run"])
    with pytest.warns(AbsurdValuesWarning, match=rf"run: {name} beyond \S+ {unit} in 8 of 11 rows \(first at "
                                                 rf"t = 0.6 s, up to 1e\+300 {unit}\)"):
        scene = build_scene([_absurd(run, name)], ["run"])
    assert np.all(np.abs(scene.upper - scene.lower) < 10.0)  # the scene stays the run's size
    assert scene.thrust_peak < 1e3 and scene.flow_peak < 1e3
    if name != "eta":
        np.testing.assert_array_equal(scene.lower, plain.lower)
    assert len(scene.notes) == 1 and not plain.notes


def test_view_warns_on_stderr(tmp_path: Path, run: neurov.Result, capsys: pytest.CaptureFixture[str]) -> None:
    pytest.importorskip("plotly")
    _absurd(run, "eta").to_npz(tmp_path / "result.npz", quiet=True)
    (tmp_path / "scenario.toml").write_text((SCENARIO_DIR / "bluerov2_depth_step.toml").read_text()
                                            .replace("duration = 100.0", "duration = 2.0"))
    assert main(["view", str(tmp_path), "--out", str(tmp_path / "replay.html")]) == 0
    err = capsys.readouterr().err
    assert f"neurov: warning: NN adaptive: eta beyond {MAX_POSITION_M:g} m in 8 of 11 rows" in err
