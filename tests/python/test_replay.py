"""The 3-D replay without a browser: what it draws where (neurov.replay.scene),
the page it writes (neurov.replay), the runs it reads back
(neurov.replay.reading) and `neurov view`'s errors (the browser:
test_replay_browser.py)."""

from __future__ import annotations

import dataclasses
import re
import subprocess
import sys
from pathlib import Path

import neurov
import numpy as np
import pytest
from neurov import cli
from neurov.errors import ResultFileError
from neurov.replay import replay
from neurov.results.load import load_result
from neurov.replay.scene import NED_TO_DISPLAY, build_scene
from neurov.results.timeseries import SERIES
from neurov.running.command import write_outputs
from neurov.config.scenario import scenario_path

plotly = pytest.importorskip("plotly")


@pytest.fixture(scope="module")
def sea() -> neurov.Result:
    """30 s of the BlueROV2 (thrusters) on a square in a sea: a current and waves."""
    scenario = neurov.load_scenario(scenario_path("bluerov2_square_sea_state_3"))
    scenario.duration = 30.0
    return neurov.simulate(scenario)


@pytest.fixture(scope="module")
def run_dir(sea: neurov.Result, tmp_path_factory: pytest.TempPathFactory) -> Path:
    out = tmp_path_factory.mktemp("runs") / "sea"
    write_outputs(sea, sea.metrics(), out)
    # The folder neurov run writes: its scenario beside the result (30 s here).
    text = Path(scenario_path("bluerov2_square_sea_state_3")).read_text(encoding="utf-8")
    (out / "scenario.toml").write_text(re.sub(r"(?m)^duration = .*$", "duration = 30.0", text), encoding="utf-8")
    return out


def _posed(result: neurov.Result, pose: list[float]) -> neurov.Result:
    """`result` with every row at one pose (NED, rad)."""
    eta = np.tile(np.asarray(pose, dtype=np.float64), (len(result.t), 1))
    return dataclasses.replace(result, eta=eta, eta_d=eta.copy())


def _hull(result: neurov.Result) -> np.ndarray:
    return build_scene([result], ["r"], max_frames=2).tracks[0].hull[0]


# --- where things are drawn ---------------------------------------------------

def test_display_axes_are_a_rotation_of_ned_so_nothing_is_mirrored() -> None:
    assert np.linalg.det(NED_TO_DISPLAY) == pytest.approx(1.0)
    np.testing.assert_array_equal(NED_TO_DISPLAY @ [1.0, 2.0, 3.0], [2.0, 1.0, -3.0])  # east, north, up


def test_the_body_points_its_bow_along_the_heading_and_its_deck_up(sea: neurov.Result) -> None:
    # Corners 0-3 are the stern, 4-7 the (smaller) bow; 0, 1, 4, 5 the deck (body -z).
    level = _hull(_posed(sea, [0.0, 0.0, 2.0, 0.0, 0.0, 0.0]))
    bow, stern, deck, keel = level[4:].mean(0), level[:4].mean(0), level[[0, 1, 4, 5]].mean(0), \
        level[[2, 3, 6, 7]].mean(0)
    assert bow[1] > stern[1] and bow[0] == pytest.approx(stern[0])  # north
    assert deck[2] > keel[2]  # the deck above the keel
    assert level.mean(0)[2] == pytest.approx(-2.0)  # 2 m deep is drawn 2 m down
    east = _hull(_posed(sea, [0.0, 0.0, 0.0, 0.0, 0.0, np.pi / 2]))
    assert east[4:].mean(0)[0] > east[:4].mean(0)[0] + 0.1  # heading 90 deg: the bow east
    rolled = _hull(_posed(sea, [0.0, 0.0, 0.0, np.pi / 2, 0.0, 0.0]))
    starboard, port = rolled[[1, 2, 5, 6]].mean(0), rolled[[0, 3, 4, 7]].mean(0)
    assert starboard[2] < port[2] - 0.1  # a positive roll puts starboard down


def test_thrust_arrows_are_each_thrusters_force_scaled_by_thrust(sea: neurov.Result) -> None:
    scene = build_scene([sea], ["r"], max_frames=10)
    track = scene.tracks[0]
    assert track.thrust_vector is not None and track.thrust_base is not None and track.force_vector is None
    thrusts = sea.thrusts[track.rows]
    lengths = np.linalg.norm(track.thrust_vector, axis=2)
    half = np.ptp(track.hull[0], axis=0).max() / 2  # the body's largest drawn extent: the longest arrow
    assert scene.reach == pytest.approx(2 * half)
    reach = scene.reach
    assert scene.thrust_peak == pytest.approx(np.abs(thrusts).max())
    np.testing.assert_allclose(lengths, np.abs(thrusts) / scene.thrust_peak * reach, rtol=1e-9, atol=1e-12)
    # At the first frame (level, heading 0) thruster 5 (vertical, pushing
    # body +z = down) draws down for a positive thrust, up for a negative one.
    f, k = 0, 4
    assert np.sign(track.thrust_vector[f, k, 2]) == -np.sign(thrusts[f, k]) or thrusts[f, k] == 0
    # The thrusters sit where the vehicle file puts them (drawn at the body's scale).
    positions = sea.scenario.vehicle_data().thrusters["positions"]
    np.testing.assert_allclose(track.thrust_base[0] - track.position[0],
                               track.body_scale * (NED_TO_DISPLAY @ neurov.rotation(*sea.eta[0, 3:]) @ positions.T).T,
                               atol=1e-12)


def test_flow_arrows_share_one_scale(sea: neurov.Result) -> None:
    scene = build_scene([sea], ["r"], max_frames=10)
    t = scene.tracks[0]
    assert t.current_vector is not None and t.wave_vector is not None
    speeds = np.linalg.norm(np.r_[sea.current[t.rows], sea.wave_velocity[t.rows]], axis=1)
    assert scene.flow_peak == pytest.approx(speeds.max())
    drawn = np.linalg.norm(np.r_[t.current_vector, t.wave_vector], axis=1)
    np.testing.assert_allclose(drawn / drawn.max(), speeds / speeds.max(), atol=1e-12)


def test_frames_are_decimated_evenly_and_a_short_run_stays_at_its_end(sea: neurov.Result) -> None:
    half = dataclasses.replace(sea, **{k: getattr(sea, k)[:76] for k in SERIES})  # 15 of the 30 s
    scene = build_scene([sea, half], ["whole", "half"], max_frames=11)
    np.testing.assert_allclose(scene.times, np.linspace(0.0, 30.0, 11))
    np.testing.assert_array_equal(scene.tracks[0].rows, np.arange(0, 151, 15))
    assert list(scene.tracks[1].rows[-5:]) == [75] * 5  # stopped at 15 s, shown there
    assert len(build_scene([sea], ["r"], max_frames=1000).times) == len(sea.t)  # never more than rows


def test_a_diverged_run_stays_at_its_last_finite_pose(sea: neurov.Result) -> None:
    eta = sea.eta.copy()
    eta[100:] = np.inf
    thrusts = sea.thrusts.copy()
    thrusts[100:] = np.nan
    broken = dataclasses.replace(sea, eta=eta, thrusts=thrusts, diverged=True)
    scene = build_scene([broken], ["r"], max_frames=31)
    track = scene.tracks[0]
    assert track.rows.max() == 99 and list(track.rows[-3:]) == [99] * 3
    for part in (track.hull, track.thrust_vector, track.position, scene.lower, scene.upper):
        assert np.all(np.isfinite(part))
    np.testing.assert_allclose(track.position[-1], NED_TO_DISPLAY @ sea.eta[99, :3])


def test_a_run_without_thrusters_draws_the_applied_force() -> None:
    scenario = neurov.load_scenario(scenario_path("nerov_depth_step"))
    scenario.duration = 10.0
    scenario.use_thrusters = False
    run = neurov.simulate(scenario)
    scene = build_scene([run], ["r"], max_frames=5)
    t = scene.tracks[0]
    assert t.thrust_vector is None and t.force_vector is not None
    assert scene.force_peak == pytest.approx(np.linalg.norm(run.tau_applied[t.rows, :3], axis=1).max())


# --- the page ---------------------------------------------------------------------

def test_the_page_is_one_file_with_frames_a_slider_and_play(sea: neurov.Result, tmp_path: Path) -> None:
    view = sea.view(max_frames=20)
    spec = view.spec
    assert len(spec["frames"]) == 20 and len(spec["layout"]["sliders"][0]["steps"]) == 20
    assert [b["label"] for b in spec["layout"]["updatemenus"][0]["buttons"]] == ["Play", "Pause"]
    assert "t = 30.0 s" in spec["frames"][-1]["layout"]["title"]["text"]
    assert "depth: NN adaptive" in spec["frames"][-1]["layout"]["title"]["text"]
    names = [d["name"] for d in spec["data"]]
    assert "desired" in names and any("current" in n for n in names) and any("wave" in n for n in names)
    assert "up = -depth" in spec["layout"]["scene"]["zaxis"]["title"]["text"]
    path = view.write_html(tmp_path / "r.html")
    html = path.read_text(encoding="utf-8")
    assert "<script src" not in html and "Plotly.newPlot" in html
    assert [p.name for p in tmp_path.iterdir()] == ["r.html"]  # no temporary file left
    # plotly.js is most of it; the 20 frames of a run add little.
    bundle = (Path(plotly.__file__).parent / "package_data" / "plotly.min.js").stat().st_size
    assert path.stat().st_size - bundle < 300_000
    assert len(view.figure.frames) == 20  # the same figure as a plotly Figure


def test_150_frames_of_a_run_add_under_a_megabyte(sea: neurov.Result) -> None:
    html = sea.view().html()
    bundle = (Path(plotly.__file__).parent / "package_data" / "plotly.min.js").stat().st_size
    assert 0 < len(html.encode()) - bundle < 1_000_000


def test_jupyter_shows_the_page_in_an_iframe(sea: neurov.Result) -> None:
    shown = sea.view(max_frames=3)._repr_html_()
    assert shown.startswith("<iframe srcdoc=\"") and "&lt;script" in shown and "<script" not in shown


def test_several_runs_on_one_path_are_told_apart(sea: neurov.Result) -> None:
    other = dataclasses.replace(sea, controller="PD")
    spec = sea.view(other, max_frames=4).spec
    names = [d["name"] for d in spec["data"]]
    assert names.count("desired") == 1  # one shared desired path
    assert any(n.startswith("NN adaptive:") for n in names) and any(n.startswith("PD:") for n in names)
    same = replay([sea, sea], max_frames=2, names=["a", "b"]).spec
    assert {d["name"].split(":")[0] for d in same["data"][1:]} == {"NN adaptive (a)", "NN adaptive (b)"}


@pytest.mark.parametrize(("args", "message"), [
    ({"results": []}, "results: expected at least one Result"),
    ({"results": ["x"]}, "results[0]: expected a neurov Result"),
    ({"max_frames": 1}, "max_frames: expected an integer >= 2"),
    ({"labels": ["a", "b"]}, "labels: expected 1 labels"),
])
def test_bad_arguments_are_named(sea: neurov.Result, args: dict, message: str) -> None:
    with pytest.raises((ValueError, TypeError), match=message.replace("[", r"\[").replace("]", r"\]")):
        replay(**{"results": [sea], **args})


def test_import_neurov_does_not_import_plotly() -> None:
    code = ("import sys, neurov, neurov.cli, neurov.replay, neurov.replay.scene; neurov.cli._parser(); "
            "assert 'plotly' not in sys.modules, 'plotly imported'")
    subprocess.run([sys.executable, "-c", code], check=True, capture_output=True, text=True)


# --- a run read back ------------------------------------------------------------

def test_a_run_folder_reads_back_whole(sea: neurov.Result, run_dir: Path) -> None:
    for path in (run_dir, run_dir / "result.npz"):
        back = load_result(path)
        for name in SERIES:
            np.testing.assert_array_equal(getattr(back, name), getattr(sea, name), err_msg=name)
            assert getattr(back, name).dtype == getattr(sea, name).dtype
        assert (back.controller, back.diverged, back.scenario.name) == (sea.controller, False, sea.scenario.name)
        assert back.scenario.use_thrusters


# --- neurov view ----------------------------------------------------------------

def test_neurov_view_writes_the_replay(run_dir: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    out = tmp_path / "replay.html"
    assert cli.main(["view", str(run_dir), str(run_dir / "result.npz"), "--out", str(out), "--frames", "5"]) == 0
    said = capsys.readouterr().out
    assert "wrote" in said and "5 frames, 2 runs" in said
    html = out.read_text(encoding="utf-8")
    assert html.count('"name":"4"') == 1 and '"name":"5"' not in html  # frames 0-4


def _npz_without(run_dir: Path, path: Path, **changes: object) -> Path:
    with np.load(run_dir / "result.npz") as z:
        arrays = {k: z[k] for k in z.files}
    arrays.update(changes)
    np.savez(path, **{k: v for k, v in arrays.items() if v is not None})
    return path


@pytest.mark.parametrize(("make", "message"), [
    (lambda d, t: t / "missing", "RESULT '{p}': no such file or folder"),
    (lambda d, t: t, "RESULT '{p}': a folder without a run's result file"),
    (lambda d, t: d / "metrics.json", "RESULT '{p}': unknown kind of result file '.json'"),
    (lambda d, t: _written(t / "x.npz", b"not a zip"), "RESULT '{p}': not a .npz archive"),
    (lambda d, t: _npz_without(d, t / "x.npz", eta=None), "RESULT '{p}': array 'eta' is missing"),
    (lambda d, t: _npz_without(d, t / "x.npz", eta=np.zeros((151, 5))),
     "RESULT '{p}': array 'eta' is float64 (151, 5), expected float64 (151, 6)"),
    (lambda d, t: _npz_without(d, t / "x.npz", faults=np.zeros(151)),
     "RESULT '{p}': array 'faults' is float64 (151,), expected uint8 (151)"),
])
def test_neurov_view_names_a_bad_result(run_dir: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str],
                                        make, message: str) -> None:
    out = tmp_path / "replay.html"
    out.write_text("an older replay", encoding="utf-8")
    bad = make(run_dir, _folder(tmp_path / "in"))
    assert cli.main(["view", str(run_dir), str(bad), "--out", str(out)]) == 1
    err = capsys.readouterr().err
    assert err.startswith("neurov: error: " + message.format(p=bad)), err
    assert out.read_text(encoding="utf-8") == "an older replay"  # nothing lost


def _written(path: Path, data: bytes) -> Path:
    path.write_bytes(data)
    return path


def _folder(path: Path) -> Path:
    path.mkdir(exist_ok=True)
    return path


@pytest.mark.parametrize(("out", "message"), [
    (lambda t: t, "--out '{o}': is a folder"),
    (lambda t: t / "no" / "r.html", "--out '{o}': the folder '{t}/no' does not exist"),
])
def test_neurov_view_names_a_bad_out(run_dir: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str],
                                     out, message: str) -> None:
    target = out(tmp_path)
    assert cli.main(["view", str(run_dir), "--out", str(target)]) == 1
    assert capsys.readouterr().err.startswith("neurov: error: " + message.format(o=target, t=tmp_path))


def test_neurov_view_needs_two_frames(run_dir: Path, capsys: pytest.CaptureFixture[str]) -> None:
    with pytest.raises(SystemExit) as stop:
        cli.main(["view", str(run_dir), "--frames", "1"])
    assert stop.value.code == 2 and "--frames must be >= 2" in capsys.readouterr().err


def test_result_file_error_is_a_neurov_error() -> None:
    assert issubclass(ResultFileError, neurov.NeurovError)
    with pytest.raises(ResultFileError, match="^x-missing: no such file"):
        load_result("x-missing")
