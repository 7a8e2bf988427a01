"""The logs users have, read for identification: a CSV with a mapping file,
ROS 2 and ROS 1 bags (written here with rosbags), an ArduSub tlog (written
here with pymavlink); each gives the same fit as the run's own log where
the format loses nothing, and fits within each other's intervals where it
rounds (a tlog's float32 values and integer PWM)."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from identify_runs import excitation_run

import neurov
from neurov.identification import LogError, read_log
from neurov.identification.neurov_log import log_from_result
from neurov.config.vehicle_file import preset_path

ENU_FLU = np.array([1, -1, -1, 1, -1, -1.0])


def _ros_frames(r: neurov.Result) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The run in ROS's frames: ENU world, FLU body."""
    eta = r.eta_estimate.copy()
    enu = np.column_stack([eta[:, 1], eta[:, 0], -eta[:, 2], eta[:, 3], -eta[:, 4],
                           np.pi / 2 - eta[:, 5]])
    return enu, r.nu_estimate * ENU_FLU, (r.tau_applied + r.disturbance) * ENU_FLU


def _compare(a: neurov.identification.Log, b: neurov.identification.Log, atol: float, tau_atol: float = 0) -> None:
    np.testing.assert_allclose(a.t, b.t, atol=1e-12)
    np.testing.assert_allclose(a.nu, b.nu, atol=atol)
    np.testing.assert_allclose(a.tau, b.tau, atol=max(atol, tau_atol))
    d = a.eta - b.eta
    d[:, 3:] = (d[:, 3:] + np.pi) % (2 * np.pi) - np.pi
    np.testing.assert_allclose(d, 0, atol=atol)


def test_a_csv_with_a_mapping_reads_units_and_frames(tmp_path: Path) -> None:
    import pandas as pd

    r = excitation_run("nerov", 20.0)
    eta, nu, tau = _ros_frames(r)
    cols = {"time_ms": r.t * 1e3}
    for k, n in enumerate(("px", "py", "pz")):
        cols[n] = eta[:, k] * 100  # cm
    for k, n in enumerate(("roll", "pitch", "yaw")):
        cols[n] = np.degrees(eta[:, 3 + k])
    for k, n in enumerate(("vx", "vy", "vz", "wx", "wy", "wz")):
        cols[n] = nu[:, k] * (100 if k < 3 else 180 / np.pi)  # cm/s, deg/s
    for k, n in enumerate(("fx", "fy", "fz", "mx", "my", "mz")):
        cols[n] = tau[:, k]
    pd.DataFrame(cols).to_csv(tmp_path / "mine.csv", index=False)
    (tmp_path / "map.toml").write_text('''
format = "csv"
body_frame = "flu"
world_frame = "enu"
time = { column = "time_ms", unit = "ms" }
[signals.eta]
columns = ["px", "py", "pz", "roll", "pitch", "yaw"]
units = ["cm", "cm", "cm", "deg", "deg", "deg"]
[signals.nu]
columns = ["vx", "vy", "vz", "wx", "wy", "wz"]
units = ["cm/s", "cm/s", "cm/s", "deg/s", "deg/s", "deg/s"]
[signals.tau]
columns = ["fx", "fy", "fz", "mx", "my", "mz"]
units = ["N", "N", "N", "N m", "N m", "N m"]
''')
    log = read_log(tmp_path / "mine.csv", tmp_path / "map.toml")
    _compare(log, log_from_result(r), 1e-9)
    (tmp_path / "bad.toml").write_text((tmp_path / "map.toml").read_text().replace('"cm/s", "cm/s", "cm/s"',
                                                                                '"cm", "cm/s", "cm/s"'))
    with pytest.raises(LogError, match=r"bad\.toml: signals\.nu\.units\[0\]: 'cm' is not a unit of velocity"):
        read_log(tmp_path / "mine.csv", tmp_path / "bad.toml")
    (tmp_path / "gone.toml").write_text((tmp_path / "map.toml").read_text().replace('"fz"', '"fzz"'))
    with pytest.raises(LogError, match=r"mine\.csv: missing column\(s\) \['fzz'\] that .*gone\.toml names"):
        read_log(tmp_path / "mine.csv", tmp_path / "gone.toml")


def _quaternion(rpy: np.ndarray) -> np.ndarray:
    cr, sr = np.cos(rpy[0] / 2), np.sin(rpy[0] / 2)
    cp, sp = np.cos(rpy[1] / 2), np.sin(rpy[1] / 2)
    cy, sy = np.cos(rpy[2] / 2), np.sin(rpy[2] / 2)
    return np.array([sr * cp * cy - cr * sp * sy, cr * sp * cy + sr * cp * sy,
                     cr * cp * sy - sr * sp * cy, cr * cp * cy + sr * sp * sy])


def _write_bag(path: Path, r: neurov.Result, ros1: bool, sensors: bool = False) -> None:
    """The run as a bag: odometry and the body wrench; with `sensors` also
    an IMU, a pressure sensor (fresh water at 997 kg/m^3, 101000 Pa at the
    surface) and the thrusters' thrusts (NEROV's six, unstamped, the bag's
    receive time)."""
    from rosbags.typesys import Stores, get_typestore

    store = get_typestore(Stores.ROS1_NOETIC if ros1 else Stores.ROS2_HUMBLE)
    T = store.types
    eta, nu, tau = _ros_frames(r)
    if ros1:
        from rosbags.rosbag1 import Writer

        writer, serialize = Writer(path), store.serialize_ros1
    else:
        from rosbags.rosbag2 import Writer

        writer, serialize = Writer(path, version=8), store.serialize_cdr
    odom_t, wrench_t = "nav_msgs/msg/Odometry", "geometry_msgs/msg/WrenchStamped"
    with writer:
        c_odom = writer.add_connection("/rov/odometry", odom_t, typestore=store)
        c_wrench = writer.add_connection("/rov/wrench", wrench_t, typestore=store)
        imu_t, pressure_t = "sensor_msgs/msg/Imu", "sensor_msgs/msg/FluidPressure"
        cmd_t = "std_msgs/msg/Float64MultiArray"
        if sensors:
            c_imu = writer.add_connection("/rov/imu", imu_t, typestore=store)
            c_pressure = writer.add_connection("/rov/pressure", pressure_t, typestore=store)
            c_cmd = writer.add_connection("/rov/thrusters", cmd_t, typestore=store)
            matrix = neurov.config.vehicle_file.load_thrusters(preset_path("nerov"))["matrix"]
            # Each thruster's thrust that gives the body wrench (neurov's frame) exactly.
            thrust = (np.linalg.solve(matrix, (r.tau_applied + r.disturbance).T)).T
        for k, t in enumerate(r.t):
            ns = int(round(t * 1e9))
            stamp = T["builtin_interfaces/msg/Time"](sec=ns // 10**9, nanosec=ns % 10**9)
            header = (T["std_msgs/msg/Header"](seq=k, stamp=stamp, frame_id="odom") if ros1 else
                      T["std_msgs/msg/Header"](stamp=stamp, frame_id="odom"))
            q = _quaternion(eta[k, 3:])
            pose = T["geometry_msgs/msg/PoseWithCovariance"](
                pose=T["geometry_msgs/msg/Pose"](
                    position=T["geometry_msgs/msg/Point"](x=eta[k, 0], y=eta[k, 1], z=eta[k, 2]),
                    orientation=T["geometry_msgs/msg/Quaternion"](x=q[0], y=q[1], z=q[2], w=q[3])),
                covariance=np.zeros(36))
            v3 = T["geometry_msgs/msg/Vector3"]
            twist = T["geometry_msgs/msg/TwistWithCovariance"](
                twist=T["geometry_msgs/msg/Twist"](linear=v3(x=nu[k, 0], y=nu[k, 1], z=nu[k, 2]),
                                                    angular=v3(x=nu[k, 3], y=nu[k, 4], z=nu[k, 5])),
                covariance=np.zeros(36))
            odom = T[odom_t](header=header, child_frame_id="base_link", pose=pose, twist=twist)
            wrench = T[wrench_t](header=header, wrench=T["geometry_msgs/msg/Wrench"](
                force=v3(x=tau[k, 0], y=tau[k, 1], z=tau[k, 2]),
                torque=v3(x=tau[k, 3], y=tau[k, 4], z=tau[k, 5])))
            writer.write(c_odom, ns, serialize(odom, odom_t))
            writer.write(c_wrench, ns, serialize(wrench, wrench_t))
            if sensors:
                imu = T[imu_t](header=header, orientation=pose.pose.orientation,
                               orientation_covariance=np.zeros(9),
                               angular_velocity=twist.twist.angular, angular_velocity_covariance=np.zeros(9),
                               linear_acceleration=v3(x=0.0, y=0.0, z=9.81),
                               linear_acceleration_covariance=np.zeros(9))
                depth = -eta[k, 2]
                pressure = T[pressure_t](header=header, fluid_pressure=101000.0 + 997.0 * 9.80665 * depth,
                                         variance=0.0)
                layout = T["std_msgs/msg/MultiArrayLayout"](dim=[], data_offset=0)
                cmd = T[cmd_t](layout=layout, data=np.ascontiguousarray(thrust[k], dtype=np.float64))
                writer.write(c_imu, ns, serialize(imu, imu_t))
                writer.write(c_pressure, ns, serialize(pressure, pressure_t))
                writer.write(c_cmd, ns, serialize(cmd, cmd_t))


def test_ros2_and_ros1_bags_give_the_run_s_own_fit(tmp_path: Path) -> None:
    r = excitation_run("nerov", 20.0)
    (tmp_path / "map.toml").write_text('format = "rosbag"\nbody_frame = "flu"\nworld_frame = "enu"\n'
                                       '[topics]\nodometry = "/rov/odometry"\nwrench = "/rov/wrench"\n')
    reference = neurov.identify(log_from_result(r), preset_path("nerov"), replicates=20,
                                output_error=False)
    for ros1, name in ((False, "run_ros2"), (True, "run.bag")):
        _write_bag(tmp_path / name, r, ros1)
        log = read_log(tmp_path / name, tmp_path / "map.toml")
        _compare(log, log_from_result(r), 1e-9)
        fit = neurov.identify(log, preset_path("nerov"), replicates=20, output_error=False)
        np.testing.assert_allclose(fit.theta, reference.theta, rtol=1e-7)
    (tmp_path / "wrong.toml").write_text((tmp_path / "map.toml").read_text().replace("/rov/wrench",
                                                                                    "/rov/thrust"))
    with pytest.raises(LogError, match=r"run\.bag: no topic '/rov/thrust'"):
        read_log(tmp_path / "run.bag", tmp_path / "wrong.toml")


SENSOR_MAP = """format = "rosbag"
body_frame = "flu"
world_frame = "enu"
water_density = 997.0
surface_pressure = 101000.0
thruster_command = "N"
[topics]
odometry = "/rov/odometry"
imu = "/rov/imu"
pressure = "/rov/pressure"
thrusters = "/rov/thrusters"
"""


def test_imu_pressure_and_thruster_topics_give_the_run_s_own_fit(tmp_path: Path) -> None:
    r = excitation_run("nerov", 20.0)
    thrusters = neurov.config.vehicle_file.load_thrusters(preset_path("nerov"))
    (tmp_path / "map.toml").write_text(SENSOR_MAP)
    reference = neurov.identify(log_from_result(r), preset_path("nerov"), replicates=20,
                                output_error=False)
    for ros1, name in ((False, "run_ros2"), (True, "run.bag")):
        _write_bag(tmp_path / name, r, ros1, sensors=True)
        log = read_log(tmp_path / name, tmp_path / "map.toml", thrusters)
        _compare(log, log_from_result(r), 1e-9)
        # The ROS 1 bag through identify's own reading (path and mapping).
        fit = neurov.identify(tmp_path / name if ros1 else log, preset_path("nerov"),
                              mapping=tmp_path / "map.toml", replicates=20, output_error=False)
        np.testing.assert_allclose(fit.theta, reference.theta, rtol=1e-7)
    bad = {"no_density": SENSOR_MAP.replace("water_density = 997.0\n", ""),
           "pwm": SENSOR_MAP.replace('thruster_command = "N"', 'thruster_command = "pwm"'),
           "both": SENSOR_MAP + 'wrench = "/rov/wrench"\n',
           "typo": SENSOR_MAP + 'imus = "/rov/imu"\n'}
    errors = {"no_density": r"no_density\.toml: water_density: expected a number > 0 \(needed with a pressure",
              "pwm": r"run\.bag: /rov/thrusters: PWM commands need the template's \[thrusters\.curve\]",
              "both": r"both\.toml: topics: expected one of 'wrench' and 'thrusters'",
              "typo": r"typo\.toml: topics\.imus: unknown"}
    for key, text in bad.items():
        (tmp_path / f"{key}.toml").write_text(text)
        with pytest.raises(LogError, match=errors[key]):
            read_log(tmp_path / "run.bag", tmp_path / f"{key}.toml", thrusters)


def _pwm(thrust: np.ndarray, curve: neurov._core.ThrusterCurveConfig) -> np.ndarray:
    """The integer PWM an ESC gets for each thrust: the curve's table inverted
    either side of its dead band (the curve is at its reference voltage)."""
    table = np.asarray(curve.table)
    neg, pos = table[table[:, 1] < 0], table[table[:, 1] > 0]
    lo_edge = table[table[:, 1] == 0][0, 0]
    hi_edge = table[table[:, 1] == 0][-1, 0]
    cmd = np.where(thrust > 0, np.interp(thrust, np.r_[0, pos[:, 1]], np.r_[hi_edge, pos[:, 0]]),
                   np.interp(thrust, np.r_[neg[:, 1], 0], np.r_[neg[:, 0], lo_edge]))
    return np.where(thrust == 0, 1500, np.round(cmd)).astype(int)


def _ardusub_run() -> tuple[neurov.Result, dict, np.ndarray]:
    """A noisy BlueROV2 run, its thrusters, and the whole force (the
    excitation included) as the eight thrusters' integer PWM."""
    r = excitation_run("bluerov2", 30.0, noise=0.01)
    thrusters = neurov.config.vehicle_file.load_thrusters(preset_path("bluerov2_heavy"))
    tau = r.tau_applied + r.disturbance
    f = np.array([neurov.allocate_thrust(thrusters["matrix"], x)[0] for x in tau])
    pwm = np.column_stack([_pwm(f[:, i], c) for i, c in enumerate(thrusters["curves"])])
    return r, thrusters, pwm


def _write_tlog(path: Path, r: neurov.Result, pwm: np.ndarray) -> None:
    import struct

    from pymavlink.dialects.v20 import ardupilotmega as mavlink

    mav = mavlink.MAVLink(None, srcSystem=1, srcComponent=1)
    eta, nu = r.eta_estimate, r.nu_estimate
    with open(path, "wb") as out:
        for k, t in enumerate(r.t):
            ms = int(round(t * 1e3))
            v_ned = neurov.rotation(*eta[k, 3:]) @ nu[k, :3]
            for msg in (mavlink.MAVLink_attitude_message(ms, *eta[k, 3:], *nu[k, 3:]),
                        mavlink.MAVLink_local_position_ned_message(ms, *eta[k, :3], *v_ned),
                        mavlink.MAVLink_servo_output_raw_message(ms * 1000, 0, *pwm[k])):
                out.write(struct.pack(">Q", 1_700_000_000_000_000 + ms * 1000) + msg.pack(mav))


def test_an_ardusub_tlog_fits_within_the_run_s_intervals(tmp_path: Path) -> None:
    r, thrusters, pwm = _ardusub_run()
    _write_tlog(tmp_path / "dive.tlog", r, pwm)
    (tmp_path / "map.toml").write_text('format = "tlog"\n')
    log = read_log(tmp_path / "dive.tlog", tmp_path / "map.toml", thrusters)
    # float32 values; 1 us of PWM is up to 0.2 N of a T200's thrust.
    _compare(log, log_from_result(r), 1e-5, tau_atol=0.5)
    # Equation error alone, fast: the same data give the same stage-1 bias either way.
    a = neurov.identify(log, preset_path("bluerov2_heavy"), replicates=100, output_error=False)
    b = neurov.identify(log_from_result(r), preset_path("bluerov2_heavy"), replicates=100,
                        output_error=False)
    assert a.fitted == b.fitted

    def inside(x: float, iv: np.ndarray) -> bool:
        return bool(iv[0] <= x <= iv[1])

    both = [inside(b.theta[i], a.interval[i]) and inside(a.theta[i], b.interval[i]) for i in a.fitted]
    # Each fit inside the other's interval; the integer PWM's yaw moment moves
    # N_r (true value 0, its interval clipped there) to the edge of the run's
    # interval (measured: 0.0052 against [0, 0.0052]): it still lies in one of the two.
    assert sum(both) >= len(both) - 1
    assert all(inside(b.theta[i], a.interval[i]) or inside(a.theta[i], b.interval[i]) for i in a.fitted)
    (tmp_path / "nerov.toml").write_text('format = "tlog"\n')
    with pytest.raises(LogError, match=r"needs the template's \[thrusters\] with a \[thrusters.curve\]"):
        neurov.identify(tmp_path / "dive.tlog", preset_path("nerov"), mapping=tmp_path / "nerov.toml")


def _dataflash_fmt(type_id: int, name: str, fmt: str, columns: str) -> bytes:
    """A DataFlash FMT message (type 128, ArduPilot's own layout
    "BBnNZ"): it defines message `type_id` as `name` with the struct `fmt`."""
    import struct

    length = 3 + struct.calcsize("<" + fmt)
    return b"\xa3\x95\x80" + struct.pack("<BB4s16s64s", type_id, length, name.encode(), fmt.encode(),
                                          columns.encode())


def _write_dataflash(path: Path, r: neurov.Result, pwm: np.ndarray, *, rcou: bool = True) -> None:
    """The run as an ArduSub DataFlash log, byte by byte (pymavlink has no
    DataFlash writer): FMT messages, then ATT (degrees), IMU (rad/s; a
    second IMU, I = 1, with other values), XKF1 (EKF3 core 0, and core 1
    with other values) and RCOU (integer PWM) at each row."""
    import struct

    types = {"ATT": (129, "Qffffff", "TimeUS,DesRoll,Roll,DesPitch,Pitch,DesYaw,Yaw"),
             "IMU": (130, "QBffffff", "TimeUS,I,GyrX,GyrY,GyrZ,AccX,AccY,AccZ"),
             "XKF1": (131, "QBffffffffff", "TimeUS,C,Roll,Pitch,Yaw,VN,VE,VD,dPD,PN,PE,PD"),
             "RCOU": (132, "Q" + "H" * 14, "TimeUS," + ",".join(f"C{i}" for i in range(1, 15)))}
    if not rcou:
        del types["RCOU"]

    def msg(name: str, *values: float) -> bytes:
        type_id, fmt, _ = types[name]
        return b"\xa3\x95" + bytes([type_id]) + struct.pack("<" + fmt, *values)

    eta, nu = r.eta_estimate, r.nu_estimate
    with open(path, "wb") as out:
        for name, (type_id, fmt, cols) in types.items():
            out.write(_dataflash_fmt(type_id, name, fmt, cols))
        for k, t in enumerate(r.t):
            us = int(round(t * 1e6))
            deg = np.degrees(eta[k, 3:])
            v_ned = neurov.rotation(*eta[k, 3:]) @ nu[k, :3]
            out.write(msg("ATT", us, *(x for d in deg for x in (0.0, d))))
            out.write(msg("IMU", us, 0, *nu[k, 3:], 0.0, 0.0, -9.81))
            out.write(msg("IMU", us, 1, *(nu[k, 3:] + 0.5), 0.0, 0.0, -9.81))
            for core, off in ((0, 0.0), (1, 3.0)):
                out.write(msg("XKF1", us, core, *deg, *(v_ned + off), 0.0, *(eta[k, :3] + off)))
            if rcou:
                out.write(msg("RCOU", us, *pwm[k], *[1500] * (14 - pwm.shape[1])))


def test_an_ardusub_dataflash_log_reads_as_its_tlog(tmp_path: Path) -> None:
    r, thrusters, pwm = _ardusub_run()
    _write_tlog(tmp_path / "dive.tlog", r, pwm)
    _write_dataflash(tmp_path / "dive.bin", r, pwm)
    (tmp_path / "tlog.toml").write_text('format = "tlog"\n')
    (tmp_path / "bin.toml").write_text('format = "dataflash"\n')
    tlog = read_log(tmp_path / "dive.tlog", tmp_path / "tlog.toml", thrusters)
    log = read_log(tmp_path / "dive.bin", tmp_path / "bin.toml", thrusters)
    _compare(log, log_from_result(r), 1e-5, tau_atol=0.5)
    # The same integer PWM: the same force to the last bit.
    np.testing.assert_array_equal(log.tau, tlog.tau)
    a = neurov.identify(log, preset_path("bluerov2_heavy"), replicates=20, output_error=False)
    b = neurov.identify(tlog, preset_path("bluerov2_heavy"), replicates=20, output_error=False)
    assert a.fitted == b.fitted
    # float32 degrees against float32 radians: the fits agree to far inside their intervals.
    np.testing.assert_allclose(a.theta, b.theta, rtol=1e-4, atol=1e-6)
    _write_dataflash(tmp_path / "norc.bin", r, pwm, rcou=False)
    with pytest.raises(LogError, match=r"norc\.bin: no RCOU message"):
        read_log(tmp_path / "norc.bin", tmp_path / "bin.toml", thrusters)
    (tmp_path / "nine.toml").write_text('format = "dataflash"\nservo_channels = [1, 2, 3, 4, 5, 6, 7, 9]\n')
    nine = read_log(tmp_path / "dive.bin", tmp_path / "nine.toml", thrusters)
    assert not np.allclose(nine.tau, log.tau)  # channel 9 is not thruster 8's
