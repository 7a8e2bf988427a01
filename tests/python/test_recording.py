"""Runs as ROS 2 / MCAP recordings (neurov.recording): every message read
with an independent reader (rosbags, with its own ROS 2 Humble message
definitions) equals the run after undoing the frames (ENU/FLU of REP 103 to
NED/FRD, worked out here by hand), timestamps included; the run reads back
exactly; a recorded path is a scenario's command."""

from __future__ import annotations

import dataclasses
import subprocess
import sys
from pathlib import Path
from typing import Any

import numpy as np
import pytest

import neurov
from neurov.errors import RecordingError, ScenarioError
from neurov.results.timeseries import SERIES
from neurov.config.reading import load_scenario

pytest.importorskip("mcap_ros2")
rosbags = pytest.importorskip("rosbags")

# A BlueROV2 with thrusters and raw sensing (an IMU, no estimator): every topic is written.
SENSED = """
name = "sensed"
duration = 3.0
dt = 0.2
seed = 3
[vehicle]
preset = "bluerov2_heavy"
thrusters = true
[initial]
eta = [0.5, -0.3, 1.0, 0.1, -0.05, 2.5]
nu = [0.2, 0.1, -0.1, 0.05, 0.02, -0.1]
[command]
type = "helix"
radius = 2.0
period = 20.0
start = 0.0
[controller]
type = "pd"
kd = [50, 50, 75, 1.5, 1.5, 1.5]
[sensors]
usbl = { rate = 1.0, noise = 0.5 }
dvl = { rate = 5.0, noise = 0.01 }
depth = { rate = 10.0, noise = 0.02 }
imu = { rate = 50.0, attitude_noise = 0.005, gyro_noise = 0.001 }
[estimator]
type = "none"
"""

SQUARE = """
name = "square"
duration = 30.0
dt = 0.2
[command]
type = "square"
side = 2.0
speed = 0.5
start = 1.0
turn_time = 2.0
[controller]
type = "pd"
"""

# R_enu_ned and R_frd_flu (= R_flu_frd): the frames' definitions, independent of neurov.recording.frames.
A = np.array([[0.0, 1, 0], [1, 0, 0], [0, 0, -1]])
B = np.diag([1.0, -1, -1])


def _rot_ned_frd(phi: float, theta: float, psi: float) -> np.ndarray:
    cf, sf, ct, st, cp, sp = np.cos(phi), np.sin(phi), np.cos(theta), np.sin(theta), np.cos(psi), np.sin(psi)
    rz = np.array([[cp, -sp, 0], [sp, cp, 0], [0, 0, 1]])
    ry = np.array([[ct, 0, st], [0, 1, 0], [-st, 0, ct]])
    rx = np.array([[1, 0, 0], [0, cf, -sf], [0, sf, cf]])
    return rz @ ry @ rx


def _rot_of_quaternion(q: Any) -> np.ndarray:
    x, y, z, w = q.x, q.y, q.z, q.w
    return np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
                     [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
                     [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)]])


def _vec(v: Any) -> np.ndarray:
    return np.array([v.x, v.y, v.z])


def _check_pose(pose: Any, eta: np.ndarray) -> None:
    """A ROS pose (map, base_link) is neurov's NED/FRD pose `eta`."""
    np.testing.assert_allclose(A.T @ _vec(pose.position), eta[:3], rtol=0, atol=1e-12)
    np.testing.assert_allclose(A.T @ _rot_of_quaternion(pose.orientation) @ B, _rot_ned_frd(*eta[3:]),
                               rtol=0, atol=1e-12)


def _check_body(linear: Any, angular: Any, v: np.ndarray) -> None:
    np.testing.assert_allclose(np.concatenate([B @ _vec(linear), B @ _vec(angular)]), v, rtol=0, atol=1e-12)


def _write(tmp_path: Path, name: str, text: str) -> Path:
    path = tmp_path / name
    path.write_text(text)
    return path


@pytest.fixture(scope="module")
def sensed(tmp_path_factory: pytest.TempPathFactory) -> tuple[neurov.Result, Path]:
    folder = tmp_path_factory.mktemp("sensed")
    result = neurov.simulate(load_scenario(_write(folder, "sensed.toml", SENSED)))
    return result, result.to_mcap(folder / "run.mcap")


def _read_all(path: Path) -> dict[str, list[tuple[int, Any]]]:
    from rosbags.highlevel import AnyReader
    from rosbags.typesys import Stores, get_typestore

    found: dict[str, list[tuple[int, Any]]] = {}
    with AnyReader([path], default_typestore=get_typestore(Stores.ROS2_HUMBLE)) as reader:
        for conn, log_ns, raw in reader.messages():
            found.setdefault(conn.topic, []).append((log_ns, reader.deserialize(raw, conn.msgtype)))
        types = {c.topic: c.msgtype for c in reader.connections}
    assert types == {"/tf": "tf2_msgs/msg/TFMessage", "/tf_static": "tf2_msgs/msg/TFMessage",
                     "/odometry": "nav_msgs/msg/Odometry", "/odometry/estimate": "nav_msgs/msg/Odometry",
                     "/desired_pose": "geometry_msgs/msg/PoseStamped",
                     "/command_pose": "geometry_msgs/msg/PoseStamped",
                     "/wrench/demanded": "geometry_msgs/msg/WrenchStamped",
                     "/wrench/applied": "geometry_msgs/msg/WrenchStamped", "/imu": "sensor_msgs/msg/Imu",
                     "/thrusts": "std_msgs/msg/Float64MultiArray"}
    return found


def test_every_message_is_the_run_in_ros_frames_read_by_rosbags(sensed: tuple[neurov.Result, Path]) -> None:
    result, path = sensed
    assert np.any(result.eta_estimate != result.eta)  # the sensors' noise: the two odometries differ
    messages = _read_all(path)
    ns = [round(t * 1e9) for t in result.t.tolist()]
    for topic, found in messages.items():
        if topic == "/tf_static":
            continue
        assert [log for log, _ in found] == ns, topic
        for (log, msg), k in zip(found, range(len(ns))):
            stamped = msg.transforms[0] if topic == "/tf" else msg
            if hasattr(stamped, "header"):
                assert stamped.header.stamp.sec * 10**9 + stamped.header.stamp.nanosec == ns[k], topic
    c = result.scenario.simulation.command
    for k in range(len(ns)):
        (_, odom), (_, est) = messages["/odometry"][k], messages["/odometry/estimate"][k]
        for msg, eta, nu in ((odom, result.eta[k], result.nu[k]),
                             (est, result.eta_estimate[k], result.nu_estimate[k])):
            assert (msg.header.frame_id, msg.child_frame_id) == ("map", "base_link")
            _check_pose(msg.pose.pose, eta)
            _check_body(msg.twist.twist.linear, msg.twist.twist.angular, nu)
        tf = messages["/tf"][k][1].transforms[0]
        assert (tf.header.frame_id, tf.child_frame_id) == ("map", "base_link")
        _check_pose(type("P", (), {"position": tf.transform.translation,
                                   "orientation": tf.transform.rotation})(), result.eta[k])
        _check_pose(messages["/desired_pose"][k][1].pose, result.eta_d[k])
        _check_pose(messages["/command_pose"][k][1].pose, c.at(result.t[k]))
        for topic, tau in (("/wrench/demanded", result.tau_demanded[k]), ("/wrench/applied", result.tau_applied[k])):
            w = messages[topic][k][1]
            assert w.header.frame_id == "base_link"
            _check_body(w.wrench.force, w.wrench.torque, tau)
        imu = messages["/imu"][k][1]
        np.testing.assert_allclose(A.T @ _rot_of_quaternion(imu.orientation) @ B,
                                   _rot_ned_frd(*result.eta_estimate[k, 3:]), rtol=0, atol=1e-12)
        np.testing.assert_allclose(B @ _vec(imu.angular_velocity), result.nu_estimate[k, 3:], rtol=0, atol=1e-12)
        assert imu.linear_acceleration_covariance[0] == -1  # not measured
        np.testing.assert_array_equal(messages["/thrusts"][k][1].data, result.thrusts[k])
    (_, static), = messages["/tf_static"]
    frames = {(t.header.frame_id, t.child_frame_id): _rot_of_quaternion(t.transform.rotation)
              for t in static.transforms}
    np.testing.assert_allclose(frames[("map", "map_ned")], A, atol=1e-15)
    np.testing.assert_allclose(frames[("base_link", "base_link_frd")], B, atol=1e-15)


def test_a_recording_reads_back_as_the_run(sensed: tuple[neurov.Result, Path]) -> None:
    from neurov.recording.mcap_reader import read_mcap

    result, path = sensed
    back = read_mcap(path)
    for name in SERIES:
        np.testing.assert_allclose(getattr(back, name), getattr(result, name), rtol=0, atol=1e-12, err_msg=name)
        assert getattr(back, name).dtype == getattr(result, name).dtype
    assert (back.controller, back.diverged, back.wall_time) == (result.controller, result.diverged, result.wall_time)
    assert back.scenario.describe() == result.scenario.describe()
    assert back.metrics() == result.metrics()


def test_neurov_run_format_mcap_streams_the_same_recording(tmp_path: Path) -> None:
    from neurov.cli import main
    from neurov.recording.mcap_reader import read_mcap

    scenario = _write(tmp_path, "sensed.toml", SENSED)
    assert main(["run", str(scenario), "--out", str(tmp_path / "out"), "--format", "mcap"]) == 0
    assert sorted(p.name for p in (tmp_path / "out").iterdir()) == ["metrics.json", "result.mcap", "result.npz", "scenario.toml"]
    back = read_mcap(tmp_path / "out" / "result.mcap")
    again = neurov.simulate(load_scenario(scenario))
    for name in SERIES:
        np.testing.assert_array_equal(getattr(back, name), getattr(again, name), err_msg=name)
    # A second run in csv replaces the recording, not keeps it beside the new rows.
    assert main(["run", str(scenario), "--out", str(tmp_path / "out")]) == 0
    assert not (tmp_path / "out" / "result.mcap").exists()


def test_a_stopped_mcap_run_keeps_its_messages(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    from neurov.cli import main
    from neurov.recording.mcap_reader import read_mcap
    from neurov.running.stream import _Sinks

    add = _Sinks.add

    def add_then_ctrl_c(self: _Sinks, raw: dict[str, Any]) -> int:
        add(self, raw)
        raise KeyboardInterrupt

    monkeypatch.setattr(_Sinks, "add", add_then_ctrl_c)
    out = tmp_path / "out"
    assert main(["run", str(_write(tmp_path, "sensed.toml", SENSED)), "--out", str(out), "--format", "mcap"]) == 130
    kept = tmp_path / "out.partial"
    assert sorted(p.name for p in kept.iterdir()) == ["metrics.json", "result.mcap"] and not out.exists()
    rows = [log for log, _ in _read_all(kept / "result.mcap")["/odometry"]]
    assert rows == [round(k * 0.2 * 1e9) for k in range(16)]  # the chunk written before Ctrl-C: the whole 3 s
    with pytest.raises(RecordingError, match="no attachment 'result.npz'"):
        read_mcap(kept / "result.mcap")


def test_format_mcap_without_out_is_a_usage_error(capsys: pytest.CaptureFixture[str]) -> None:
    from neurov.cli import main

    with pytest.raises(SystemExit) as stop:
        main(["run", "paper_fig3", "--format", "mcap"])
    assert stop.value.code == 2 and "--format mcap needs --out DIR" in capsys.readouterr().err


def test_read_mcap_names_what_is_wrong(tmp_path: Path, sensed: tuple[neurov.Result, Path]) -> None:
    from mcap_ros2.writer import Writer

    from neurov.recording.mcap_reader import read_mcap

    result, _ = sensed
    with pytest.raises(RecordingError, match="no such MCAP file"):
        read_mcap(tmp_path / "missing.mcap")
    _write(tmp_path, "text.mcap", "not a recording")
    with pytest.raises(RecordingError, match="text.mcap: not a readable MCAP file"):
        read_mcap(tmp_path / "text.mcap")
    with (tmp_path / "other.mcap").open("wb") as f:
        Writer(f).finish()
    with pytest.raises(RecordingError, match="no attachment 'result.npz'"):
        read_mcap(tmp_path / "other.mcap")
    changed = result.scenario.replace()
    changed.duration = 2.0
    neurov.simulate(changed).to_mcap(tmp_path / "changed.mcap")
    with pytest.raises(RecordingError, match="differs from its file scenario.toml in simulation"):
        read_mcap(tmp_path / "changed.mcap")
    assert read_mcap(tmp_path / "changed.mcap", scenario=changed).scenario is changed


def test_a_recorded_command_reproduces_the_run_s_desired_path(tmp_path: Path) -> None:
    first = neurov.simulate(load_scenario(_write(tmp_path, "square.toml", SQUARE)))
    first.to_mcap(tmp_path / "square.mcap")
    replay = SQUARE.replace('type = "square"\nside = 2.0\nspeed = 0.5\nstart = 1.0\nturn_time = 2.0',
                            'type = "recorded"\nfile = "square.mcap"\ntopic = "/command_pose"')
    scenario = load_scenario(_write(tmp_path, "replay.toml", replay))
    assert scenario.command.args == {"file": str(tmp_path / "square.mcap"), "topic": "/command_pose", "start": 0.0}
    again = neurov.simulate(scenario)
    assert first.eta_d[:, 5].max() > 4  # the heading turned past pi and was unwrapped
    np.testing.assert_allclose(again.eta_d, first.eta_d, rtol=0, atol=1e-12)
    np.testing.assert_allclose(again.eta_d_dot, first.eta_d_dot, rtol=0, atol=1e-12)
    # Odometry reads too: the poses of /odometry are the run's (heading unwrapped).
    from neurov.recording.recorded_path import recorded_path

    times, poses = recorded_path(tmp_path / "square.mcap", "/odometry", start=2.0)
    np.testing.assert_allclose(times, first.t + 2.0, rtol=0, atol=1e-12)
    np.testing.assert_allclose(poses, first.eta, rtol=0, atol=1e-12)


def test_a_ros2_bag_of_poses_is_a_command(tmp_path: Path) -> None:
    """A rosbag2 folder (written by rosbags, stamps of the wall clock) of
    PoseStamped in map/ENU gives neurov's NED poses, times from `start`."""
    from rosbags.rosbag2 import Writer
    from rosbags.typesys import Stores, get_typestore
    from scipy.spatial.transform import Rotation

    store = get_typestore(Stores.ROS2_HUMBLE)
    T = store.types
    times = np.array([0.0, 2.5, 5.0, 9.0])
    ned = np.array([[0.0, 0, 1, 0, 0, 0], [3, 1, 1.5, 0.1, -0.05, 2.0], [4, 4, 2, 0, 0.1, 3.0],
                    [0, 5, 2, -0.1, 0, 4.5]])  # the heading passes pi
    epoch = 1_700_000_000 * 10**9
    with Writer(tmp_path / "bag", version=8) as writer:
        conn = writer.add_connection("/path", "geometry_msgs/msg/PoseStamped", typestore=store)
        for t, pose in zip(times, ned):
            ns = epoch + round(t * 1e9)
            q = Rotation.from_matrix(A @ _rot_ned_frd(*pose[3:]) @ B).as_quat()
            msg = T["geometry_msgs/msg/PoseStamped"](
                header=T["std_msgs/msg/Header"](stamp=T["builtin_interfaces/msg/Time"](
                    sec=ns // 10**9, nanosec=ns % 10**9), frame_id="map"),
                pose=T["geometry_msgs/msg/Pose"](
                    position=T["geometry_msgs/msg/Point"](x=pose[1], y=pose[0], z=-pose[2]),
                    orientation=T["geometry_msgs/msg/Quaternion"](x=q[0], y=q[1], z=q[2], w=q[3])))
            writer.write(conn, ns, store.serialize_cdr(msg, "geometry_msgs/msg/PoseStamped"))
    text = SQUARE.replace('type = "square"\nside = 2.0\nspeed = 0.5\nstart = 1.0\nturn_time = 2.0',
                          'type = "recorded"\nfile = "bag"\ntopic = "/path"\nstart = 1.5')
    command = load_scenario(_write(tmp_path, "replay.toml", text)).command
    np.testing.assert_allclose(command.times, times + 1.5, rtol=0, atol=1e-12)
    np.testing.assert_allclose(command.poses, ned, rtol=0, atol=1e-12)


@pytest.mark.parametrize("command, message", [
    ('file = "none.mcap"\ntopic = "/command_pose"', r"command\.file: no such bag or MCAP file: .*none\.mcap"),
    ('file = "bad.mcap"\ntopic = "/command_pose"', r"command\.file: .*bad\.mcap: not a readable ROS 2 bag or MCAP"),
    ('file = "square.mcap"\ntopic = "/nowhere"', r"command\.topic: .*no topic '/nowhere' \(the bag has \["),
    ('file = "square.mcap"\ntopic = "/wrench/applied"',
     r"command\.topic: .*'/wrench/applied' is geometry_msgs/msg/WrenchStamped, expected "
     r"geometry_msgs/msg/PoseStamped or nav_msgs/msg/Odometry"),
    ('file = "short.mcap"\ntopic = "/command_pose"', r"command\.topic: .*'/command_pose' has 1 pose\(s\); a path "
                                                     r"needs at least 2"),
    ('file = "twice.mcap"\ntopic = "/command_pose"', r"command\.topic: .*two poses stamped 0 ns; a path needs "
                                                     r"strictly increasing stamps"),
    ('file = "twice.mcap"\ntopic = "/odometry"', r"command\.topic: .*'/odometry' has non-finite positions"),
    ('topic = "/command_pose"', r"command\.file: "),
    ('file = "square.mcap"\ntopic = "/command_pose"\nstart = "soon"', r"command\.start: expected a number"),
])
def test_a_bad_recorded_command_names_the_field(tmp_path: Path, command: str, message: str) -> None:
    square = neurov.simulate(load_scenario(_write(tmp_path, "square.toml", SQUARE.replace("30.0", "0.2"))))
    square.to_mcap(tmp_path / "square.mcap")
    from neurov.recording.mcap_writer import McapRecorder

    short = McapRecorder(tmp_path / "short.mcap", square.scenario, 0)  # one row: one pose on each topic
    short.add(_one_row(square))
    short.discard()
    twice = McapRecorder(tmp_path / "twice.mcap", square.scenario, 0)  # two rows at t = 0, one pose NaN
    rows = dataclasses.replace(square, **{name: getattr(square, name)[[0, 0]] for name in SERIES})
    rows.t[:], rows.eta[1, 0] = 0.0, np.nan
    twice.add(rows)
    twice.discard()
    _write(tmp_path, "bad.mcap", "not a bag")
    text = SQUARE.replace('type = "square"\nside = 2.0\nspeed = 0.5\nstart = 1.0\nturn_time = 2.0',
                          f'type = "recorded"\n{command}')
    with pytest.raises(ScenarioError, match=r"replay\.toml: " + message):
        load_scenario(_write(tmp_path, "replay.toml", text))


def _one_row(result: neurov.Result) -> neurov.Result:
    return dataclasses.replace(result, **{name: getattr(result, name)[:1] for name in SERIES})


def test_without_the_ros_extra_the_error_says_what_to_install(tmp_path: Path, monkeypatch: pytest.MonkeyPatch,
                                                              sensed: tuple[neurov.Result, Path]) -> None:
    from neurov.recording.mcap_reader import read_mcap

    result, path = sensed
    monkeypatch.setitem(sys.modules, "mcap_ros2.writer", None)  # import mcap_ros2.writer raises ImportError
    monkeypatch.setitem(sys.modules, "mcap.reader", None)
    with pytest.raises(RecordingError, match=r"needs mcap and mcap-ros2-support: pip install 'neurov\[ros\]'"):
        result.to_mcap(tmp_path / "run.mcap")
    assert not (tmp_path / "run.mcap").exists()
    with pytest.raises(RecordingError, match=r"needs mcap: pip install 'neurov\[ros\]'"):
        read_mcap(path)


def test_import_neurov_imports_no_mcap() -> None:
    code = ("import sys, neurov; r = neurov.Result; "
            "bad = [m for m in ('mcap', 'mcap_ros2', 'rosbags', 'neurov.recording.mcap_writer') if m in sys.modules]; "
            "assert not bad, bad")
    subprocess.run([sys.executable, "-c", code], check=True)
