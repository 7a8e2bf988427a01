"""Identification on real logs nobody here wrote (tests/data/logs/, with
their sources and licences) and on synthetic logs built to reproduce each
failure real logs showed: a tlog read with no mapping and its weak
excitation named, a DataFlash log of another frame refused by name, array
topics mapped, PWM in integer arrays read, two files with their own clocks joined and irregular
sampling resampled, dead rates named, a time column in milliseconds
labelled seconds, a template of the wrong structure, an overflowing output
error, inseparable parameters named, and no traceback anywhere."""

from __future__ import annotations

import re
from pathlib import Path
from types import SimpleNamespace

import numpy as np
import pytest
from identify_runs import excitation_run

import neurov
from neurov.cli import main
from neurov.config.vehicle_file import preset_path
from neurov.identification import read_log
from neurov.identification.ardusub_params import read_log_parameters
from neurov.identification.guards import fit_warnings, inseparable
from neurov.identification.log import make_log
from neurov.identification.survey import analyse_logs, report_lines
from neurov.identification.neurov_log import log_from_result
from neurov.identification.parameters import free_indices

DATA = Path(__file__).resolve().parents[1] / "data" / "logs" / "ardusub_log_tools"
TLOG = DATA / "bluerov2_heavy_excerpt.tlog"
BIN = DATA / "bluerov2_vectored.BIN"


def _heavy_thrusters() -> dict:
    return neurov.config.vehicle_file.load_thrusters(preset_path("bluerov2_heavy"))


def test_the_real_tlog_is_read_with_no_mapping_and_its_parameters_used() -> None:
    params = read_log_parameters(TLOG)
    assert len(params) == 887 and params["FRAME_CONFIG"] == 2.0 and params["MOT_1_DIRECTION"] == -1.0
    log = read_log(TLOG, None, _heavy_thrusters())
    assert len(log.t) == 320 and log.cut == 5245 - 320  # the disarmed rows cut
    notes = " ".join(log.notes)
    assert "FRAME_CONFIG 2: Vectored 6DOF (BlueROV2 Heavy)" in notes
    assert "1:-1, 2:-1, 3:+1, 4:+1, 5:-1, 6:+1, 7:+1, 8:-1" in notes
    assert "SERVO_OUTPUT_RAW at 2 Hz" in notes and "ATTITUDE at 20 Hz" in notes


def test_the_real_tlog_s_weak_excitation_is_named_and_nothing_is_written(tmp_path: Path, capsys) -> None:
    out = tmp_path / "fitted.toml"
    assert main(["identify", str(TLOG), "--vehicle", "bluerov2_heavy", "--out", str(out)]) == 1
    printed = capsys.readouterr()
    assert "Traceback" not in printed.err + printed.out
    assert "no vehicle file written" in printed.err and not out.exists()
    assert "-X_udot: not excited" in printed.err
    # Said first, in words: armed for 16 s of 263, the force outside the dead band logged 4 times in surge.
    lines = printed.out.splitlines()
    lines = lines[next(i for i, line in enumerate(lines) if line.startswith("Log report:")):]
    assert lines[1].endswith("the vehicle was armed on only 6.1 % of the log (320 of 5245 rows, 207.0 s to "
                             "222.9 s after the first): the disarmed rows are cut (no thrust; the vehicle "
                             "may be out of the water)")
    assert lines[2].startswith("Problem: surge: the force outside the dead band was logged only 4 times")
    assert re.search(r"^X\s+N\s+0\.376", printed.out, re.M)  # the force changes 0.376 times a second
    assert "Excitation plan for the pilot (ArduSub)" in printed.out
    plan = tmp_path / "fitted_excitation.toml"
    assert (tmp_path / "fitted.report.txt").is_file() and plan.is_file()
    s = neurov.load_scenario(plan)  # the plan is a scenario neurov runs
    assert len(s.disturbances) == 12  # two sines in each of the six DOF


def test_a_tlog_never_armed_is_refused_with_the_reason(tmp_path: Path, capsys) -> None:
    import struct

    from pymavlink.dialects.v20 import ardupilotmega as mavlink

    mav = mavlink.MAVLink(None, srcSystem=1, srcComponent=1)
    with open(tmp_path / "bench.tlog", "wb") as out:
        for k in range(50):
            beat = mavlink.MAVLink_heartbeat_message(12, 3, 0, 19, 3, 3)  # a submarine, ArduPilot, disarmed
            out.write(struct.pack(">Q", 1_700_000_000_000_000 + k * 100_000) + beat.pack(mav))
    assert main(["identify", str(tmp_path / "bench.tlog"), "--vehicle", "bluerov2_heavy", "--report"]) == 1
    err = capsys.readouterr().err
    assert "the vehicle was never armed in this log (HEARTBEAT)" in err and "Traceback" not in err


def test_report_alone_exits_0(tmp_path: Path, capsys) -> None:
    assert main(["identify", str(TLOG), "--vehicle", "bluerov2_heavy", "--report",
                 "--out", str(tmp_path / "f.toml")]) == 0
    printed = capsys.readouterr().out
    assert printed.startswith("Log report: 320 rows, 16.0 s")
    assert "Read: " in printed and "MOT_PWM_MIN/MAX 1100/1900 us" in printed


def test_the_real_dataflash_log_of_another_frame_is_refused_by_name(tmp_path: Path, capsys) -> None:
    assert read_log_parameters(BIN)["FRAME_CONFIG"] == 1.0
    assert main(["identify", str(BIN), "--vehicle", "bluerov2_heavy", "--out", str(tmp_path / "f.toml")]) == 1
    err = capsys.readouterr().err
    assert "FRAME_CONFIG 1 is Vectored (BlueROV2) with 6 thrusters; the template has 8" in err
    assert "Traceback" not in err and not (tmp_path / "f.toml").exists()


def _rows(r: neurov.Result) -> tuple[np.ndarray, ...]:
    return r.t, r.eta_estimate, r.nu_estimate, r.tau_applied + r.disturbance


@pytest.mark.parametrize("name", ["junk.tlog", "junk.BIN"])
def test_a_file_that_is_not_a_log_is_refused_in_one_line(name: str, tmp_path: Path, capsys) -> None:
    (tmp_path / name).write_bytes(np.random.default_rng(0).bytes(5000))
    assert main(["identify", str(tmp_path / name), "--vehicle", "bluerov2_heavy", "--report"]) == 1
    printed = capsys.readouterr()
    assert printed.out == "" and len(printed.err.splitlines()) == 1 and name in printed.err


def test_dead_rates_are_named_and_their_parameters_left_at_the_template() -> None:
    t, eta, nu, tau = _rows(excitation_run("nerov", 30.0))
    nu = nu.copy()
    nu[:, 3:] = 1e-7 * np.sin(np.arange(len(t)))[:, None]  # never filled in: ~1e-7 rad/s throughout
    log = make_log("pool", t, eta, nu, tau)
    report = analyse_logs([log], free_indices(None))
    text = "\n".join(report_lines(report))
    for name in ("p", "q", "r"):
        assert f"Problem: {name} [rad/s] never moves" in text
    assert report.verdicts[15][0] == "no" and report.verdicts[21][0] == "no"  # N_r, N_r|r|
    fit = neurov.identify(log, preset_path("nerov"), replicates=20, output_error=False)
    assert 15 not in fit.fitted and "not excited: left at the template's value" in fit.reasons[15]
    assert fit.theta[15] == fit.theta_template[15]


@pytest.mark.parametrize("estimator", ["auto", True])
def test_dead_rates_are_left_out_of_the_output_error(estimator: object) -> None:
    """The student AUV's pool runs (rates never filled in, ~1e-7 rad/s): the
    output error scaled each velocity by its RMS, so the dead rates' residual
    (~1e7 per rad/s) outweighed everything and the fit walked to -X_udot ~ 1e5
    (truth 30), or its step was singular (the rates' filter gains untold). A
    velocity that never moves is now left out of the residual, and said."""
    t, eta, nu, tau = _rows(excitation_run("nerov", 30.0))
    nu = nu.copy()
    nu[:, 3:] = 1e-7 * np.sin(np.arange(len(t)))[:, None]
    fit = neurov.identify(make_log("pool", t, eta, nu, tau), preset_path("nerov"), replicates=20,
                          estimator=estimator)
    assert fit.stages == "equation error, then output error"
    assert any(w.startswith("output error: p, q, r never move in the logs") for w in fit.warnings)
    names = [neurov._core.THETA_NAMES[i] for i in fit.fitted]  # the rotational DOF's left at the template
    assert names == ["-X_udot", "-Y_vdot", "-Z_wdot", "X_u", "Y_v", "Z_w", "X_u|u|", "Y_v|v|", "Z_w|w|"]
    np.testing.assert_allclose(fit.theta[fit.fitted], fit.theta_template[fit.fitted], rtol=0.1)


def test_a_time_column_in_milliseconds_labelled_seconds_is_flagged() -> None:
    t, eta, nu, tau = _rows(excitation_run("nerov", 30.0))
    report = analyse_logs([make_log("ms.csv", t * 1000, eta, nu, tau)], free_indices(None))
    assert any("implausible for a vehicle's log" in p and "milliseconds" in p for p in report.problems)
    assert any("a time or velocity unit is wrong" in p for p in report.problems)
    right = analyse_logs([make_log("s.csv", t, eta, nu, tau)], free_indices(None))
    assert not right.problems
    fit = neurov.identify(make_log("ms.csv", t * 1000, eta, nu, tau), preset_path("nerov"), replicates=20,
                          output_error=False)
    assert any("implausible for a vehicle's log" in w for w in fit.warnings)  # a fit says it too


def test_two_files_with_their_own_clocks_joined_and_irregular_sampling_resampled(tmp_path: Path) -> None:
    import pandas as pd

    t, eta, nu, tau = _rows(excitation_run("nerov", 60.0))
    rng = np.random.default_rng(1)
    keep = np.sort(np.r_[0, rng.choice(np.arange(1, len(t)), size=len(t) * 3 // 5, replace=False)])
    nav = {"time": t[keep]} | {f"e{k}": eta[keep, k] for k in range(6)} | {f"n{k}": nu[keep, k] for k in range(6)}
    pd.DataFrame(nav).to_csv(tmp_path / "nav.csv", index=False)
    wrench = {"stamp_ns": np.round(t * 1e9).astype(np.int64)} | {f"f{k}": tau[:, k] for k in range(6)}
    pd.DataFrame(wrench).to_csv(tmp_path / "wrench.csv", index=False)
    cols = lambda p: "[" + ", ".join(f'"{p}{k}"' for k in range(6)) + "]"  # noqa: E731
    (tmp_path / "map.toml").write_text(
        'format = "csv"\ntime = { column = "time", unit = "s" }\n'
        f'[signals.eta]\ncolumns = {cols("e")}\nunits = ["m", "m", "m", "rad", "rad", "rad"]\n'
        f'[signals.nu]\ncolumns = {cols("n")}\nunits = ["m/s", "m/s", "m/s", "rad/s", "rad/s", "rad/s"]\n'
        f'[signals.tau]\nfile = "wrench.csv"\ntime = {{ column = "stamp_ns", unit = "ns" }}\n'
        f'columns = {cols("f")}\nunits = ["N", "N", "N", "N m", "N m", "N m"]\n')
    log = read_log(tmp_path / "nav.csv", tmp_path / "map.toml")
    notes = " ".join(log.notes)
    assert "signals.tau from wrench.csv joined onto nav.csv's clock: its latest sample at or before" in notes
    assert "irregular sampling" in notes and "resampled to" in notes
    assert len(log.segments) <= 3  # not hundreds of pieces
    # The force at a resampled row is the wrench file's latest sample: exact.
    k = np.searchsorted(t, log.t[5], side="right") - 1
    np.testing.assert_allclose(log.tau[5], tau[k], rtol=0, atol=1e-9)
    fit = neurov.identify(log, preset_path("nerov"), replicates=20, output_error=False)
    assert np.all(np.isfinite(fit.theta))


def test_array_topics_are_mapped_by_element_index(tmp_path: Path) -> None:
    from rosbags.rosbag1 import Writer
    from rosbags.typesys import Stores, get_typestore

    r = excitation_run("nerov", 10.0)
    store = get_typestore(Stores.ROS1_NOETIC)
    T = store.types
    f32, f64 = "std_msgs/msg/Float32MultiArray", "std_msgs/msg/Float64MultiArray"
    layout = T["std_msgs/msg/MultiArrayLayout"](dim=[], data_offset=0)
    with Writer(tmp_path / "thesis.bag") as w:
        c_ekf = w.add_connection("/ekf/attitude", f32, typestore=store)
        c_pos = w.add_connection("/ekf/position", f64, typestore=store)
        c_wr = w.add_connection("/wrench", "geometry_msgs/msg/WrenchStamped", typestore=store)
        for k, t in enumerate(r.t):
            ns = 10**9 + int(round(t * 1e9))
            ekf = np.r_[7.0, np.degrees(r.eta_estimate[k, 3:]), np.degrees(r.nu_estimate[k, 3:])]
            w.write(c_ekf, ns, store.serialize_ros1(T[f32](layout=layout, data=ekf.astype(np.float32)), f32))
            pos = np.r_[r.eta_estimate[k, :3], r.nu_estimate[k, :3]]
            w.write(c_pos, ns, store.serialize_ros1(T[f64](layout=layout, data=pos), f64))
            stamp = T["builtin_interfaces/msg/Time"](sec=ns // 10**9, nanosec=ns % 10**9)
            v3, tau = T["geometry_msgs/msg/Vector3"], r.tau_applied[k] + r.disturbance[k]
            msg = T["geometry_msgs/msg/WrenchStamped"](
                header=T["std_msgs/msg/Header"](seq=k, stamp=stamp, frame_id="base"),
                wrench=T["geometry_msgs/msg/Wrench"](force=v3(x=tau[0], y=tau[1], z=tau[2]),
                                                     torque=v3(x=tau[3], y=tau[4], z=tau[5])))
            w.write(c_wr, ns, store.serialize_ros1(msg, "geometry_msgs/msg/WrenchStamped"))
    deg = '"deg", "deg", "deg", "deg/s", "deg/s", "deg/s"'
    (tmp_path / "map.toml").write_text(
        'format = "rosbag"\n[topics]\nwrench = "/wrench"\n'
        '[[arrays]]\ntopic = "/ekf/position"\nelements = { x = 0, y = 1, z = 2, u = 3, v = 4, w = 5 }\n'
        '[[arrays]]\ntopic = "/ekf/attitude"\n'
        'elements = { roll = 1, pitch = 2, yaw = 3, p = 4, q = 5, r = 6 }\n'
        f'units = {{ {", ".join(f"{n} = {u}" for n, u in zip(("roll", "pitch", "yaw", "p", "q", "r"), deg.split(", ")))} }}\n')
    log = read_log(tmp_path / "thesis.bag", tmp_path / "map.toml")
    np.testing.assert_allclose(log.nu[:, 3:], r.nu_estimate[:, 3:], atol=1e-5)  # float32 in degrees
    np.testing.assert_allclose(log.eta[:, :3], r.eta_estimate[:, :3], atol=1e-12)
    (tmp_path / "bad.toml").write_text('format = "rosbag"\n[topics]\nwrench = "/wrench"\n'
                                       '[[arrays]]\ntopic = "/ekf/attitude"\nelements = { roll = 9 }\n')
    with pytest.raises(neurov.identification.LogError, match="has 7 elements; the mapping reads element 9"):
        read_log(tmp_path / "thesis.bag", tmp_path / "bad.toml")


def test_a_template_of_the_wrong_structure_is_warned(tmp_path: Path) -> None:
    r = excitation_run("nerov", 60.0)
    text = re.sub(r"(?m)^(linear|quadratic)_damping\s*=.*$", r"\1_damping = [0, 0, 0, 0, 0, 0]",
                  preset_path("nerov").read_text())
    (tmp_path / "nodamp.toml").write_text(text)
    held = log_from_result(excitation_run("nerov", 60.0, heldout=True))
    fit = neurov.identify(log_from_result(r), tmp_path / "nodamp.toml", free="mass", replicates=20,
                          heldout=[held])
    assert fit.theta[0] > 300  # the true mass is 185: the missing damping ends up in it
    assert any(w.startswith("fit of the free run on the fitted log") and "structure" in w
               for w in fit.warnings)
    assert any(w.startswith("held-out fit (free run) on") and "below 50 %" in w for w in fit.warnings)
    # The right structure passes both verdicts.
    good = neurov.identify(log_from_result(r), preset_path("nerov"), replicates=20, heldout=[held])
    assert not any("free run" in w for w in good.warnings), good.warnings


def test_an_overflowing_output_error_step_is_rejected_and_counted(monkeypatch) -> None:
    from neurov.identification import output_error

    real = output_error.simulate_segments
    calls = [0]

    def flaky(*args, **kwargs):
        calls[0] += 1
        if calls[0] % 7 == 3:
            raise ValueError("rk4_segments: segment 0, step 1: the result overflowed to a non-finite number")
        return real(*args, **kwargs)

    monkeypatch.setattr(output_error, "simulate_segments", flaky)
    fit = neurov.identify(log_from_result(excitation_run("nerov", 20.0)), preset_path("nerov"), replicates=20)
    note = next(w for w in fit.warnings if w.startswith("output error:"))
    assert re.match(r"output error: \d+ trial step\(s\) overflowed", note)
    assert fit.stages == "equation error, then output error"
    monkeypatch.setattr(output_error, "simulate_segments",
                        lambda *a, **k: (_ for _ in ()).throw(ValueError("overflowed")))
    fit = neurov.identify(log_from_result(excitation_run("nerov", 20.0)), preset_path("nerov"), replicates=20)
    assert fit.stages.startswith("equation error (the output-error stage failed")
    assert any("equation-error estimate is written" in w for w in fit.warnings)


def test_a_singular_output_error_step_names_what_it_cannot_separate(monkeypatch) -> None:
    """The thesis BlueROV's yaw run (built into a CSV by hand) stopped the
    output error with numpy's bare "Singular matrix" from its last step."""
    from neurov.identification import output_error

    real = output_error._profiled_blocks

    def tied(*args, **kwargs):  # the first two fitted parameters made inseparable
        b = real(*args, **kwargs)
        b.gram[:, 1, :], b.gram[:, :, 1] = b.gram[:, 0, :], b.gram[:, :, 0]
        return b

    monkeypatch.setattr(output_error, "_profiled_blocks", tied)
    fit = neurov.identify(log_from_result(excitation_run("nerov", 20.0)), preset_path("nerov"), replicates=20)
    assert fit.stages.startswith("equation error (the output-error stage failed: its normal equations are "
                                 "singular at the solution: the data cannot separate (")
    assert re.search(r"\(\+1\.00 -X_udot -1\.00 -Y_vdot\)|\(-1\.00 -X_udot \+1\.00 -Y_vdot\)", fit.stages)


def test_inseparable_parameters_are_named_as_combinations() -> None:
    a = np.array([[1.0, 2.0, 0.0], [2.0, 4.0, 0.0], [0.0, 0.0, 3.0]])  # columns 0 and 1 move together
    text = inseparable(a, [0, 6, 10])
    assert text.startswith("the data cannot separate (") and "m" in text and "-Z_wdot" in text
    assert "X_u" not in text.replace("X_u|", "")


def test_zero_width_and_pinned_intervals_are_flagged() -> None:
    theta0 = np.zeros(24)
    theta0[[4, 10]] = [6.0, 13.0]
    theta = theta0.copy()
    theta[[4, 10]] = [0.0, 13.0]
    interval = np.full((24, 2), np.nan)
    interval[4] = [0.0, 0.0]
    interval[10] = [12.0, 14.0]
    fit = SimpleNamespace(blocks=SimpleNamespace(count=20), fitted=[4, 10])
    out = fit_warnings([], SimpleNamespace(y=np.zeros((5, 6, 24))), fit, interval, theta, theta0,
                       np.array([0.0, 0.0]), np.array([np.inf, np.inf]))
    assert any(w.startswith("zero-width interval for -X_udot") for w in out)
    assert any(w.startswith("-X_udot is pinned at its bound 0") for w in out)
    assert not any("X_u:" in w or w.startswith("X_u ") for w in out)


def test_a_parameter_moved_from_a_template_zero_is_drawn_as_its_value(tmp_path: Path) -> None:
    from neurov.identification.plots import panels, plot_identification

    fit = neurov.identify(log_from_result(excitation_run("bluerov2", 20.0)), preset_path("bluerov2_heavy"),
                          replicates=20, output_error=False)
    rel, absolute = panels(fit)
    assert 11 in absolute and 11 not in rel  # Y_v: 0 in the template
    assert all(fit.theta_template[i] != 0 for i in rel)
    assert plot_identification(fit, tmp_path / "f.png").read_bytes()[:4] == b"\x89PNG"


def test_a_dataflash_log_s_disarmed_rows_are_cut(tmp_path: Path) -> None:
    import struct

    from test_identify_readers import _ardusub_run, _dataflash_fmt, _write_dataflash

    r, thrusters, pwm = _ardusub_run()
    _write_dataflash(tmp_path / "dive.bin", r, pwm)
    whole = read_log(tmp_path / "dive.bin", None, thrusters)

    def with_arm(name: str, events: list[tuple[float, int]]) -> Path:
        data = (tmp_path / "dive.bin").read_bytes() + _dataflash_fmt(140, "ARM", "QbIbB",
                                                                      "TimeUS,ArmState,ArmChecks,Forced,Method")
        for t, state in events:
            data += b"\xa3\x95\x8c" + struct.pack("<QbIbB", int(t * 1e6), state, 0, 0, 0)
        (tmp_path / name).write_bytes(data)
        return tmp_path / name

    # Disarmed at 20 s (armed before it, the state it changed from): the last 10 s cut, and said.
    log = read_log(with_arm("disarm.bin", [(20.0, 0)]), None, thrusters)
    assert log.t[-1] < 20.0 and len(log.t) < len(whole.t)
    assert any("armed on 66.6 % of the log (400 of 601 rows" in n for n in log.notes)
    np.testing.assert_array_equal(log.tau, whole.tau[:len(log.t)])
    # Armed only from 25 s: a problem, said first in the report.
    late = read_log(with_arm("late.bin", [(0.0, 0), (25.0, 1)]), None, thrusters)
    assert late.problems and "armed on only 16.8 % of the log (101 of 601 rows" in late.problems[0]
    with pytest.raises(neurov.identification.LogError, match=r"never\.bin \(ARM\): the vehicle was never armed"):
        read_log(with_arm("never.bin", [(0.0, 0)]), None, thrusters)


def test_integer_pwm_arrays_are_thruster_commands_and_a_missing_velocity_is_named_first(tmp_path: Path) -> None:
    """The thesis BlueROV's bags publish PWM as UInt16MultiArray: read as
    the tlog's PWM (the same thruster curves); a log with no linear velocity
    says so before any thruster mismatch."""
    from rosbags.rosbag1 import Writer
    from rosbags.typesys import Stores, get_typestore

    from neurov.identification.tlog_log import pwm_force

    r = excitation_run("bluerov2", 5.0)
    thrusters = _heavy_thrusters()
    pwm = np.random.default_rng(3).integers(1100, 1901, size=(len(r.t), 8))
    store = get_typestore(Stores.ROS1_NOETIC)
    T = store.types
    f64, u16 = "std_msgs/msg/Float64MultiArray", "std_msgs/msg/UInt16MultiArray"
    layout = T["std_msgs/msg/MultiArrayLayout"](dim=[], data_offset=0)
    with Writer(tmp_path / "pwm.bag") as w:
        c_state = w.add_connection("/state", f64, typestore=store)
        c_pwm = w.add_connection("/thrusters", u16, typestore=store)
        for k, t in enumerate(r.t):
            ns = 10**9 + int(round(t * 1e9))
            state = np.r_[r.eta_estimate[k], r.nu_estimate[k]]
            w.write(c_state, ns, store.serialize_ros1(T[f64](layout=layout, data=state), f64))
            w.write(c_pwm, ns, store.serialize_ros1(T[u16](layout=layout, data=pwm[k].astype(np.uint16)), u16))
    head = 'format = "rosbag"\nthruster_command = "pwm"\n[topics]\nthrusters = "/thrusters"\n[[arrays]]\ntopic = "/state"\n'
    (tmp_path / "all.toml").write_text(head + "elements = { " + ", ".join(
        f"{n} = {k}" for k, n in enumerate(("x", "y", "z", "roll", "pitch", "yaw", "u", "v", "w", "p", "q", "r"))) + " }\n")
    log = read_log(tmp_path / "pwm.bag", tmp_path / "all.toml", thrusters)
    np.testing.assert_allclose(log.tau, pwm_force(pwm.astype(float), thrusters)[: len(log.t)], atol=1e-12)
    (tmp_path / "rot.toml").write_text(head + "elements = { roll = 3, pitch = 4, yaw = 5, p = 9, q = 10, r = 11, z = 2 }\n")
    # No linear velocity or position (the thesis BlueROV's bags): read, those held at zero and named.
    assert read_log(tmp_path / "pwm.bag", tmp_path / "rot.toml", thrusters).absent == ("x", "y", "u", "v", "w")
    (tmp_path / "angles.toml").write_text(head + "elements = { roll = 3, pitch = 4, yaw = 5, z = 2 }\n")
    six = dict(thrusters, matrix=thrusters["matrix"][:, :6], curves=thrusters["curves"][:6])
    with pytest.raises(neurov.identification.LogError, match=r"no topic gives x, y, u, v, w, p, q, r \(.*angles\.toml"):
        read_log(tmp_path / "pwm.bag", tmp_path / "angles.toml", six)
