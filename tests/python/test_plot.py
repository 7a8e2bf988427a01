"""neurov.plotting: each function returns a Figure with the axes and lines it
documents, showing the data it should; save writes a PNG."""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
import pytest
from matplotlib.figure import Figure

from neurov import plotting as plot
from neurov.config.scenario import ThrusterFailure
from neurov.results.timeseries import Result
from neurov.running.simulation import simulate
from plot_runs import PD, assert_demanded_and_applied, nn_and_pd, square

SCENARIO = square("plot_square", 20.0)


@pytest.fixture(scope="module")
def runs() -> list[Result]:
    return nn_and_pd(SCENARIO)


@pytest.fixture(scope="module")
def no_thrusters() -> Result:
    return simulate(SCENARIO.replace(use_thrusters=False, duration=5.0))


def legend_texts(ax: object) -> list[str]:
    legend = ax.get_legend()  # type: ignore[attr-defined]
    return [t.get_text() for t in legend.get_texts()] if legend else []


def test_xy_path(runs: list[Result]) -> None:
    fig = plot.xy_path(runs, title="square")
    assert isinstance(fig, Figure)
    (ax,) = fig.axes
    desired, nn, pd = ax.lines
    # East to the right, north up: the map convention.
    np.testing.assert_array_equal(desired.get_xdata(), runs[0].eta_d[:, 1])
    np.testing.assert_array_equal(desired.get_ydata(), runs[0].eta_d[:, 0])
    np.testing.assert_array_equal(pd.get_xdata(), runs[1].eta[:, 1])
    assert desired.get_linestyle() == "-" and nn.get_linestyle() == "--" and pd.get_linestyle() == "-."
    assert legend_texts(ax) == ["desired", "NN adaptive", "PD"]
    assert "east" in ax.get_xlabel() and "[m]" in ax.get_xlabel()
    assert "north" in ax.get_ylabel() and "[m]" in ax.get_ylabel()
    assert ax.get_title() == "square"
    assert len(ax.collections) == 3  # where the desired path and each run start


def test_xy_path_single_result_and_labels(runs: list[Result]) -> None:
    fig = plot.xy_path(runs[0], labels=["mine"])
    (ax,) = fig.axes
    assert len(ax.lines) == 2
    assert legend_texts(ax) == ["desired", "mine"]


def test_xy_path_different_desired_paths(runs: list[Result], no_thrusters: Result) -> None:
    fig = plot.xy_path([runs[0], no_thrusters])
    (ax,) = fig.axes
    # One desired path per run, then the runs; the same controller twice is
    # told apart by the scenario name.
    assert len(ax.lines) == 4
    assert legend_texts(ax)[2:] == ["NN adaptive (plot_square) #1", "NN adaptive (plot_square) #2"]


def test_dof_time(runs: list[Result]) -> None:
    fig = plot.dof_time(runs)
    assert len(fig.axes) == 4
    assert all(len(ax.lines) == 3 for ax in fig.axes)
    yaw = fig.axes[3]
    np.testing.assert_allclose(yaw.lines[1].get_ydata(), np.degrees(runs[0].eta[:, 5]))
    np.testing.assert_array_equal(yaw.lines[1].get_xdata(), runs[0].t)
    assert "[deg]" in yaw.get_ylabel() and "[m]" in fig.axes[0].get_ylabel()
    assert fig.axes[-1].get_xlabel() == "t [s]"
    fig = plot.dof_time(runs[1], dofs=[2])
    assert len(fig.axes) == 1 and len(fig.axes[0].lines) == 2


def test_errors(runs: list[Result]) -> None:
    fig = plot.errors(runs, dofs=(0, 1, 2, 3, 4, 5))
    assert len(fig.axes) == 6
    assert all(len(ax.lines) == 2 for ax in fig.axes)
    np.testing.assert_allclose(fig.axes[0].lines[1].get_ydata(), runs[1].eta[:, 0] - runs[1].eta_d[:, 0])
    np.testing.assert_allclose(fig.axes[5].lines[0].get_ydata(), np.degrees(runs[0].error[:, 5]))
    assert legend_texts(fig.axes[0])[0].startswith("NN adaptive (RMS ")
    assert len(plot.errors(runs, dofs=(0, 1, 2, 5)).axes) == 4


def test_errors_leave_out_the_dofs_no_run_has_an_error_in() -> None:
    from neurov.config.reading import load_scenario
    from neurov.config.scenario import SCENARIO_DIR

    depth = simulate(load_scenario(SCENARIO_DIR / "nerov_depth_step.toml").replace(duration=12.0))
    fig = plot.errors(depth)
    assert [ax.get_ylabel() for ax in fig.axes] == ["z error [m]"]
    assert "no error in x, y, yaw (not drawn)" in fig.axes[0].get_title()
    # Asked for, a DOF without error is drawn and says so.
    asked = plot.errors(depth, dofs=(0, 2))
    assert len(asked.axes) == 2
    assert [t.get_text() for t in asked.axes[0].texts] == ["no x error in any run"]


def test_control_inputs_with_thrusts(runs: list[Result]) -> None:
    fig = plot.control_inputs(runs[0])
    forces, moments, thrusts = fig.axes
    assert_demanded_and_applied(forces, runs[0], range(3))
    assert_demanded_and_applied(moments, runs[0], range(3, 6))
    # Six thrusters plus the limits, +-250 N.
    assert len(thrusts.lines) == 6 + 2
    assert sorted(line.get_ydata()[0] for line in thrusts.lines[6:]) == [-250.0, 250.0]
    assert "[N]" in forces.get_ylabel() and "[N m]" in moments.get_ylabel() and "[N]" in thrusts.get_ylabel()
    assert len(plot.control_inputs(runs[0], show_thrusts=False).axes) == 2


def test_control_inputs_marks_a_failure() -> None:
    failing = SCENARIO.replace(duration=4.0, thruster_failures=[ThrusterFailure(index=2, time=2.0)])
    fig = plot.control_inputs(simulate(failing, PD))
    thrusts = fig.axes[2]
    assert len(thrusts.lines) == 6 + 2 + 1
    assert any(t.get_text() == "T3 fails" for t in thrusts.texts)  # index 2 is the third thruster


def test_control_inputs_show_where_the_thrusters_cannot_give_the_demand() -> None:
    from neurov.config.reading import load_scenario

    path = Path(__file__).resolve().parents[2] / "examples" / "scenarios" / "thrusters_failure.toml"
    result = simulate(load_scenario(path).replace(duration=100.0))  # T1 fails at 60 s
    forces, moments = plot.control_inputs(result).axes[:2]
    both = assert_demanded_and_applied(forces, result, range(3)) + \
        assert_demanded_and_applied(moments, result, range(3, 6))
    assert both > 0
    # The gap shaded, the demanded dashed line drawn over the applied one.
    assert forces.collections and moments.collections
    lines = forces.lines
    for k, line in enumerate(lines):
        if line.get_gid() == "demanded":
            assert lines[k - 1].get_gid() == "applied" and line.get_linestyle() != "-"


def test_control_inputs_without_thrusters(no_thrusters: Result) -> None:
    fig = plot.control_inputs(no_thrusters)
    assert len(fig.axes) == 2
    assert_demanded_and_applied(fig.axes[0], no_thrusters, range(3))
    assert_demanded_and_applied(fig.axes[1], no_thrusters, range(3, 6))


def test_adaptive_norm(runs: list[Result]) -> None:
    fig = plot.adaptive_norm(runs)
    (ax,) = fig.axes
    nn, pd = ax.lines
    np.testing.assert_array_equal(nn.get_ydata(), runs[0].adaptive_norm)
    assert np.max(nn.get_ydata()) > 0
    np.testing.assert_array_equal(pd.get_ydata(), 0.0)
    assert legend_texts(ax) == ["NN adaptive: ‖Ŵ‖_F", "PD: none"]


def test_bad_arguments(runs: list[Result]) -> None:
    with pytest.raises(ValueError, match="labels"):
        plot.xy_path(runs, labels=["one"])
    with pytest.raises(ValueError, match="at least one"):
        plot.errors([])
    with pytest.raises(ValueError, match="dofs"):
        plot.dof_time(runs, dofs=(6,))
    with pytest.raises(TypeError, match="Result"):
        plot.adaptive_norm([runs[0], "not a result"])  # type: ignore[list-item]


def test_save_writes_a_png(runs: list[Result], tmp_path: Path) -> None:
    path = plot.save(plot.xy_path(runs), tmp_path / "new" / "xy.png", dpi=60)
    assert path == tmp_path / "new" / "xy.png"
    data = path.read_bytes()
    assert data[:8] == b"\x89PNG\r\n\x1a\n"
    assert len(data) > 5000


def test_no_pyplot_state(runs: list[Result]) -> None:
    # Figures are built without pyplot, so none pile up in its registry.
    plot.dof_time(runs)
    if "matplotlib.pyplot" in sys.modules:
        assert sys.modules["matplotlib.pyplot"].get_fignums() == []
