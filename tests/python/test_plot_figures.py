"""What a reader of the figures needs: a unit on every axis, forces and
moments apart, thrusters numbered T1..Tn everywhere, where an X-Y path starts
and which way it goes, Fig. 5's caption naming the controller with the lower
error, and study plots that show few samples as points with labels in words."""

from __future__ import annotations

import dataclasses
import re
from pathlib import Path

import numpy as np
import pandas as pd
import pytest
from matplotlib.axes import Axes
from matplotlib.figure import Figure

from neurov import plotting as plot
from neurov.results.metrics import METRICS
from neurov.paper.experiments import fig5_caption, paper_scenario
from neurov.plotting.labels import metric_label, thruster_label
from neurov.paper.figures import figure_inputs, figure_xy, figure_yaw
from neurov.plotting.paths import ARROWS, mark_start_and_direction
from neurov.plotting.study import FEW_SAMPLES, BandPlotter, box_figure, plot_boxes
from neurov.config.scenario import ThrusterFailure
from neurov.results.timeseries import Result
from neurov.running.simulation import simulate
from neurov.study import load_study, metric_names
from plot_runs import PD, assert_demanded_and_applied, nn_and_pd, square

UNIT = re.compile(r"\[[^\]]+\]")
SQUARE = square("figures_square", 12.0)


@pytest.fixture(scope="module")
def runs() -> list[Result]:
    return nn_and_pd(SQUARE)


@pytest.fixture(scope="module")
def fig5_runs() -> list[Result]:
    # Long enough for the desired path to have left its start (at 5 s).
    scenario = paper_scenario("paper_fig5").replace(duration=25.0)
    linear = scenario.controller.replace(type="linear", gamma=1.0, theta0="zero",
                                 label="linear adaptive")
    return [simulate(scenario), simulate(scenario, linear)]


def _labelled(ax: Axes, which: str) -> bool:
    """`ax` has a `which` ("x" or "y") label with a unit in brackets, or
    shares that axis with an axes that has one (small multiples label the
    outer panels only)."""
    def label(a: Axes) -> str:
        return a.get_xlabel() if which == "x" else a.get_ylabel()

    shared = ax.get_shared_x_axes() if which == "x" else ax.get_shared_y_axes()
    return any(UNIT.search(label(a)) for a in shared.get_siblings(ax) if a.get_visible())


def _assert_units(fig: Figure) -> None:
    for ax in fig.axes:
        if ax.get_visible():
            assert _labelled(ax, "x"), f"x axis of {ax.get_title()!r}: {ax.get_xlabel()!r}"
            assert _labelled(ax, "y"), f"y axis of {ax.get_title()!r}: {ax.get_ylabel()!r}"


def test_every_axis_of_every_run_and_paper_figure_has_a_unit(runs: list[Result],
                                                             fig5_runs: list[Result]) -> None:
    figures = [plot.xy_path(runs), plot.dof_time(runs, dofs=range(6)), plot.errors(runs),
               plot.control_inputs(runs[0]), plot.adaptive_norm(runs),
               figure_xy(runs, "Fig. 3"), figure_inputs(runs[0]), figure_inputs(fig5_runs[0]),
               figure_yaw(fig5_runs)]
    for fig in figures:
        _assert_units(fig)


def test_fig4_draws_forces_and_moments_on_separate_axes(runs: list[Result]) -> None:
    forces, moments, thrusts = figure_inputs(runs[0]).axes
    assert "[N]" in forces.get_ylabel() and "[N m]" in moments.get_ylabel()
    assert_demanded_and_applied(forces, runs[0], range(3))
    assert_demanded_and_applied(moments, runs[0], range(3, 6))
    assert len(thrusts.lines) == runs[0].thrusts.shape[1]


def test_thrusters_are_numbered_from_one_everywhere(runs: list[Result]) -> None:
    assert [thruster_label(i) for i in range(3)] == ["T1", "T2", "T3"]
    with pytest.raises(ValueError, match="index"):
        thruster_label(-1)
    six = ["T1", "T2", "T3", "T4", "T5", "T6"]
    assert [line.get_label() for line in figure_inputs(runs[0]).axes[2].lines] == six
    thrusts = plot.control_inputs(runs[0]).axes[2]
    assert [t.get_text() for t in thrusts.get_legend().get_texts()][:6] == six
    # Index 0 in the scenario is the first thruster: T1.
    failing = SQUARE.replace(duration=3.0, thruster_failures=[ThrusterFailure(index=0, time=1.0)])
    texts = [t.get_text() for t in plot.control_inputs(simulate(failing, PD)).axes[2].texts]
    assert texts == ["T1 fails"]


def _start_and_arrows(ax: Axes) -> tuple[list, list]:
    starts = [c for c in ax.collections if c.get_gid() == "start"]
    arrows = [p for p in ax.patches if p.get_gid() == "direction"]
    return starts, arrows


def test_xy_plots_mark_the_start_and_the_direction(runs: list[Result], fig5_runs: list[Result]) -> None:
    for fig, desired in ((plot.xy_path(runs), runs[0].eta_d), (figure_xy(runs, "Fig. 3"), runs[0].eta_d),
                         (figure_yaw(fig5_runs), fig5_runs[0].eta_d)):
        ax = fig.axes[0]
        starts, arrows = _start_and_arrows(ax)
        assert len(starts) == 1
        np.testing.assert_array_equal(starts[0].get_offsets()[0], [desired[0, 1], desired[0, 0]])
        assert any(t.get_text() == "start" for t in ax.texts)
        assert len(arrows) == ARROWS


def test_arrows_point_along_the_path() -> None:
    fig = Figure()
    ax = fig.add_subplot()
    # A unit square run anticlockwise from the origin: east, north, west, south.
    east = np.array([0.0, 1.0, 1.0, 0.0, 0.0])
    north = np.array([0.0, 0.0, 1.0, 1.0, 0.0])
    mark_start_and_direction(ax, east, north)
    _, arrows = _start_and_arrows(ax)
    # Private, but the only record of where matplotlib put the arrow's ends.
    directions = [np.subtract(a._posA_posB[1], a._posA_posB[0]) for a in arrows]
    expected = [(1, 0), (0, 1), (-1, 0), (0, -1)]
    for d, e in zip(directions, expected):
        np.testing.assert_allclose(d / np.linalg.norm(d), e, atol=1e-12)
    # A hold at one point: a start, no direction.
    ax2 = Figure().add_subplot()
    mark_start_and_direction(ax2, np.zeros(5), np.zeros(5))
    starts, arrows = _start_and_arrows(ax2)
    assert len(starts) == 1 and not arrows


def test_fig5_caption_names_the_controller_with_the_lower_error(fig5_runs: list[Result]) -> None:
    caption = fig5_caption([("NN", {"rmse_yaw_rad": 0.2, "rmse_position_m": 0.05}),
                            ("linear", {"rmse_yaw_rad": 0.1, "rmse_position_m": 0.3})], after=10.0)
    assert caption == ("Over t >= 10 s: RMS yaw error NN 0.2 rad, linear 0.1 rad (linear lower); "
                       "RMS position error NN 0.05 m, linear 0.3 m (NN lower).")
    tie = fig5_caption([("a", {"rmse_yaw_rad": 0.1, "rmse_position_m": 0.1}),
                        ("b", {"rmse_yaw_rad": 0.1, "rmse_position_m": 0.2})])
    assert "(equal)" in tie and "(a lower)" in tie
    with pytest.raises(ValueError, match="compared"):
        fig5_caption([("a", {})])
    # From the runs drawn: the caption under Fig. 5 is the one computed.
    metrics = [(r.controller, r.metrics(after=2.0)) for r in fig5_runs]
    expected = fig5_caption(metrics, after=2.0)
    better = min(metrics, key=lambda m: m[1]["rmse_position_m"])[0]
    assert f"({better} lower)." in expected
    fig = figure_yaw(fig5_runs, expected)
    # No public getter in matplotlib 3.8-3.11; the caption is wrapped to fit.
    assert " ".join(fig._supxlabel.get_text().split()) == expected


def test_every_metric_has_a_label_in_words_with_a_unit() -> None:
    assert set(metric_names()) <= set(METRICS)
    for key, m in METRICS.items():
        label = metric_label(key)
        assert label == m.label and UNIT.search(label), key
        assert "_" not in label, key  # words, not a raw key
    assert metric_label("rmse_position_m") == "RMS position error [m]"


def _study_table(samples: int) -> tuple[object, pd.DataFrame]:
    study = load_study("league")
    study = dataclasses.replace(study, scenarios=study.scenarios[:2], samples=samples)
    rng = np.random.default_rng(3)
    rows = [{"scenario": s.name, "controller": c, "sample": k, study.ranking_metric: rng.uniform(0.1, 1.0)}
            for s in study.scenarios for c in study.controllers for k in range(samples)]
    return study, pd.DataFrame(rows)


def test_few_samples_are_drawn_as_points(tmp_path: Path) -> None:
    study, table = _study_table(samples=3)
    assert 3 < FEW_SAMPLES
    assert plot_boxes(study, table, tmp_path / "boxes.png").is_file()
    fig = box_figure(study, table)
    ax = fig.axes[0]
    points = [c for c in ax.collections if str(c.get_gid()).startswith("controller:")]
    assert len(points) == len(study.controllers)
    offsets = np.concatenate([p.get_offsets() for p in points])
    mine = table[table["scenario"] == study.scenarios[0].name]
    np.testing.assert_array_equal(np.sort(offsets[:, 0]), np.sort(mine[study.ranking_metric]))
    # Each controller's points sit around its own row, named at the left.
    for row, (c, p) in enumerate(zip(study.controllers, points), start=1):
        assert p.get_gid() == f"controller:{c}"
        assert np.all(np.abs(p.get_offsets()[:, 1] - row) < 0.5)
    assert [t.get_text() for t in ax.get_yticklabels()] == [study.label(c) for c in study.controllers]
    assert not ax.patches  # no boxes
    assert ax.get_xlabel() == "RMS position error [m]"
    assert "rmse_position_m" not in fig.get_suptitle()


def test_many_samples_are_drawn_as_boxes() -> None:
    study, table = _study_table(samples=FEW_SAMPLES)
    fig = box_figure(study, table)
    ax = fig.axes[0]
    assert not [c for c in ax.collections if str(c.get_gid()).startswith("controller:")]
    assert len(ax.patches) == len(study.controllers)  # one box each
    assert len(ax.lines) >= 5 * len(study.controllers)  # median, two whiskers, two caps each
    for ax in fig.axes:
        if ax.get_visible():
            assert UNIT.search(ax.get_xlabel()), ax.get_title()


def test_every_row_of_box_panels_names_the_controllers() -> None:
    # The league's twenty scenarios: seven rows of panels.
    study, table = _study_table(samples=1)
    study = dataclasses.replace(study, scenarios=load_study("league").scenarios)
    fig = box_figure(study, table)
    names = [study.label(c) for c in study.controllers]
    panels = [ax for ax in fig.axes if ax.get_visible()]
    rows = sorted({round(ax.get_position().y0, 6) for ax in panels})
    assert len(rows) == 7
    for y0 in rows:
        left = min((ax for ax in panels if round(ax.get_position().y0, 6) == y0),
                   key=lambda ax: ax.get_position().x0)
        assert all(tick.label1.get_visible() for tick in left.yaxis.get_major_ticks())
        assert [t.get_text() for t in left.get_yticklabels()] == names


def _records(study: object, scenario: str, scale: float) -> dict:
    rng = np.random.default_rng(int(scale * 10))
    return {(scenario, c, k): {"series": {"t0": 0.0, "dt": 0.5,
                                          "position_error": list(scale * rng.uniform(0.01, 1.0, 40))}}
            for c in study.controllers for k in range(study.samples)}  # type: ignore[attr-defined]


def test_one_band_figure_object_draws_each_scenario_as_a_fresh_one_would(tmp_path: Path) -> None:
    study, _ = _study_table(samples=3)
    first, second = study.scenarios  # type: ignore[attr-defined]
    records = {**_records(study, first.name, 5.0), **_records(study, second.name, 0.1)}
    reused = BandPlotter(study)
    reused.draw(records, first, tmp_path / "first.png")
    reused.draw(records, second, tmp_path / "reused.png")
    BandPlotter(study).draw(records, second, tmp_path / "fresh.png")
    assert (tmp_path / "reused.png").read_bytes() == (tmp_path / "fresh.png").read_bytes()
    _assert_units(reused.fig)


def test_grey_curves_break_at_gaps_as_a_line_would() -> None:
    from neurov.plotting.study import _finite_runs

    t = np.arange(8.0)
    y = np.array([1.0, 2.0, np.nan, 3.0, np.nan, 4.0, 5.0, 6.0])
    runs = _finite_runs(t, y)
    # The lone point at t = 3 draws nothing, as in a Line2D.
    assert [r.tolist() for r in runs] == [[[0, 1], [1, 2]], [[5, 4], [6, 5], [7, 6]]]
    assert _finite_runs(t, np.full(8, np.nan)) == []


def test_band_panels_hold_every_other_controller_in_grey(tmp_path: Path) -> None:
    study, _ = _study_table(samples=3)
    scenario = study.scenarios[0]  # type: ignore[attr-defined]
    records = _records(study, scenario.name, 1.0)
    plotter = BandPlotter(study)
    plotter.draw(records, scenario, tmp_path / "bands.png")
    n = len(study.controllers)  # type: ignore[attr-defined]
    for c, grey in plotter.others.items():
        assert len(grey.get_segments()) == n - 1
        median = plotter.median[c].get_ydata()
        assert not any(np.array_equal(seg[:, 1], median) for seg in grey.get_segments())
