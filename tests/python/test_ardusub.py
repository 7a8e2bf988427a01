"""The ArduSub controller from Python: parameters by ArduSub's names from
files and scenario keys, the named refusals and warnings, the parameter file
written back, and the closed loop on the shipped BlueROV2 scenarios."""

from __future__ import annotations

import tomllib
import warnings
from pathlib import Path

import numpy as np
import pytest

import neurov
from neurov import _core
from neurov.config.reading import scenario_from_mapping
from neurov.config.scenario import SCENARIO_DIR, ScenarioError
from neurov.laws import ardusub_params as ap

# The values the issue lists from a real BlueROV2 Heavy telemetry log.
STOCK = {"FRAME_CONFIG": 2, "ATC_ANG_RLL_P": 10, "ATC_RAT_RLL_P": 0.135, "ATC_RAT_RLL_I": 0.09,
         "ATC_RAT_RLL_D": 0.01, "ATC_RAT_YAW_P": 0.18, "ATC_INPUT_TC": 0.15, "PSC_POSZ_P": 3,
         "PSC_VELZ_P": 8, "PSC_ACCZ_P": 0.5, "PSC_ACCZ_I": 0.1, "MOT_PWM_MIN": 1100, "MOT_PWM_MAX": 1900}


def _qgc(params: dict[str, float]) -> str:
    return "# Onboard parameters\n" + "".join(f"1\t1\t{k}\t{v}\t9\n" for k, v in params.items())


def _scenario(tmp_path: Path, name: str, controller: dict, **top) -> neurov.Scenario:
    data = tomllib.loads((SCENARIO_DIR / f"{name}.toml").read_text())
    data["controller"] = controller
    data.update(top)
    return scenario_from_mapping(data, str(tmp_path / f"{name}.toml"))


def test_the_table_is_arduSubs_names_defaults_and_ranges():
    p = ap.PARAMETERS["ATC_RAT_RLL_P"]
    assert (p.default, p.min, p.max) == (0.135, 0.0, 0.3)
    cfg = _core.ArduSubConfig()
    for name, spec in ap.PARAMETERS.items():
        assert getattr(cfg, name) == pytest.approx(spec.default), name


def test_qgc_and_mavproxy_files_read_alike(tmp_path):
    (tmp_path / "a.param").write_text(_qgc({"ATC_RAT_RLL_P": 0.2, "SYSID_THISMAV": 1}))
    (tmp_path / "b.parm").write_text("# mavproxy\nATC_RAT_RLL_P 0.2\nSYSID_THISMAV,1\n\n")
    assert ap.read_parameters(tmp_path / "a.param") == ap.read_parameters(tmp_path / "b.parm") == {
        "ATC_RAT_RLL_P": 0.2, "SYSID_THISMAV": 1.0}


@pytest.mark.parametrize("text, match", [
    ("ATC_RAT_RLL_P 0.2\nthis is not a parameter line\n", r"b\.param:2: expected 'NAME VALUE'"),
    ("1\t1\tATC_RAT_RLL_P\tfast\t9\n", r"b\.param:1: ATC_RAT_RLL_P: expected a number, got 'fast'"),
    ("# only a comment\n", "no parameters"),
])
def test_garbage_in_a_param_file_is_named(tmp_path, text, match):
    (tmp_path / "b.param").write_text(text)
    with pytest.raises(ap.ArduSubParameterError, match=match):
        ap.read_parameters(tmp_path / "b.param")


def test_scenario_keys_override_the_file_and_unknown_names_suggest(tmp_path):
    (tmp_path / "vehicle.param").write_text(_qgc({**STOCK, "ATC_RAT_PIT_P": 0.15}))
    s = _scenario(tmp_path, "bluerov2_depth_step", {"type": "ardusub", "mode": "position_hold",
                                                     "params": "vehicle.param", "ATC_RAT_PIT_P": 0.2})
    c = s.controller
    assert (c.config.ATC_ANG_RLL_P, c.config.ATC_RAT_PIT_P, c.config.mode, c.config.FRAME_CONFIG) == (10, 0.2, 2, 2)
    with pytest.raises(ScenarioError, match=r"controller\.ATC_RAT_RLL_PP: unknown field; did you mean 'ATC_RAT_RLL_P'"):
        _scenario(tmp_path, "bluerov2_depth_step", {"type": "ardusub", "ATC_RAT_RLL_PP": 0.2})


def test_what_ardusub_would_not_fly_is_refused_and_out_of_range_warned(tmp_path):
    with pytest.raises(ScenarioError, match=r"controller\.ATC_RAT_YAW_I = -0\.1: expected >= 0"):
        _scenario(tmp_path, "bluerov2_depth_step", {"type": "ardusub", "FRAME_CONFIG": 2, "ATC_RAT_YAW_I": -0.1})
    with pytest.raises(ScenarioError, match=r"FRAME_CONFIG = 3: expected 1 \(vectored"):
        _scenario(tmp_path, "bluerov2_depth_step", {"type": "ardusub", "FRAME_CONFIG": 3})
    (tmp_path / "v.param").write_text(_qgc({"FRAME_CONFIG": 2, "PSC_VELZ_IMAX": 5000, "ATC_RAT_RLL_FLTT": 0}))
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        s = _scenario(tmp_path, "bluerov2_depth_step", {"type": "ardusub", "params": "v.param"})
    said = sorted(str(w.message).split(": ", 1)[1] for w in caught if w.category is ap.ArduSubRangeWarning)
    assert said == ["ATC_RAT_RLL_FLTT = 0 is outside ArduSub's documented range [1, 100] Hz; taken as ArduSub takes it",
                    "PSC_VELZ_IMAX = 5000 is outside ArduSub's documented range [1, 1000] cm/s/s; taken as ArduSub "
                    "takes it"]
    assert (s.controller.config.PSC_VELZ_IMAX, s.controller.config.ATC_RAT_RLL_FLTT) == (5000, 0)


def test_a_frame_that_does_not_fit_the_vehicle_is_named(tmp_path):
    s = _scenario(tmp_path, "bluerov2_depth_step", {"type": "ardusub"})  # ArduSub's default frame: 1
    with pytest.raises(ValueError, match=r"FRAME_CONFIG = 1 \(6 motors\) does not fit the vehicle's 8 thrusters"):
        neurov.simulate(s)


def test_the_written_param_file_reads_back(tmp_path):
    text = ap.format_param_file({"ATC_RAT_RLL_P": 0.1234567, "PSC_POSZ_P": 2.5}, ["tuned on x"])
    assert text.splitlines()[-1] == "1\t1\tPSC_POSZ_P\t2.5\t9"
    (tmp_path / "best.param").write_text(text)
    assert ap.read_parameters(tmp_path / "best.param") == {"ATC_RAT_RLL_P": 0.1234567, "PSC_POSZ_P": 2.5}


def test_pwm_and_mixing_are_visible_from_python():
    cfg = _core.ArduSubConfig()
    cfg.FRAME_CONFIG, cfg.mode, cfg.dt = 2.0, 1.0, 0.0025
    ctl = _core.ArduSubController(cfg)
    ctl.step(np.zeros(6), np.zeros(6), np.array([0, 0, 1.0, 0, 0, 0]), np.zeros(6), np.zeros(6))
    assert ctl.axis_inputs[3] == pytest.approx(-0.4002)  # hand-worked in tests/cpp/test_ardusub.cpp
    assert ctl.pwm.shape == (8,)
    np.testing.assert_allclose(ctl.pwm[4:], 1500 + 400 * 0.4002)


@pytest.mark.parametrize("name, mode", [("bluerov2_depth_step", "depth_hold"), ("bluerov2_square", "position_hold")])
def test_stock_parameters_hold_the_shipped_bluerov2_scenarios(tmp_path, name, mode):
    (tmp_path / "stock.param").write_text(_qgc(STOCK))
    s = _scenario(tmp_path, name, {"type": "ardusub", "mode": mode, "params": "stock.param"})
    r = neurov.simulate(s)
    m = r.metrics()
    assert not r.diverged
    assert m["rmse_position_m"] < 1.0, m["rmse_position_m"]


def test_a_pickled_controller_steps_as_the_original():
    import pickle

    cfg = _core.ArduSubConfig()
    cfg.FRAME_CONFIG, cfg.mode, cfg.dt = 2.0, 2.0, 0.2
    a = _core.ArduSubController(cfg)
    eta, nu, eta_d = np.array([0.3, -0.2, 1.1, 0.05, -0.02, 0.4]), np.full(6, 0.01), np.array([1, 0.5, 2, 0, 0, 0.2])
    for _ in range(3):
        a.step(eta, nu, eta_d, np.zeros(6), np.zeros(6))
    b = pickle.loads(pickle.dumps(a))
    assert a.memory.shape == (70,) and np.any(a.memory != 0)
    np.testing.assert_array_equal(a.memory, b.memory)
    np.testing.assert_array_equal(a.step(eta + 0.1, nu, eta_d, np.zeros(6), np.zeros(6)),
                                  b.step(eta + 0.1, nu, eta_d, np.zeros(6), np.zeros(6)))


def test_neurov_params_writes_a_logs_parameters_as_a_param_file(tmp_path, capsys):
    from neurov.cli import main

    (tmp_path / "vehicle.parm").write_text("ATC_RAT_RLL_P 0.2   # tuned\nSYSID_THISMAV 1\nSYSID_THISMAV 2\n")
    assert main(["params", str(tmp_path / "vehicle.parm"), "--out", str(tmp_path / "v.param")]) == 0
    assert capsys.readouterr().out.strip() == str(tmp_path / "v.param")
    assert ap.read_parameters(tmp_path / "v.param") == {"ATC_RAT_RLL_P": 0.2, "SYSID_THISMAV": 2.0}
    (tmp_path / "bad.tlog").write_bytes(b"\x00\x01not a log")
    assert main(["params", str(tmp_path / "bad.tlog")]) == 1
    assert "bad.tlog" in capsys.readouterr().err


def test_a_telemetry_logs_param_values_are_read(tmp_path):
    # A .tlog as MAVProxy and QGroundControl write one: each MAVLink message
    # after its 8-byte big-endian microsecond time stamp (written here with
    # pymavlink; no public ArduSub log was found to ship).
    mavutil = pytest.importorskip("pymavlink.mavutil")
    mav = mavutil.mavlink.MAVLink(None, srcSystem=1, srcComponent=1)
    out = bytearray()
    for i, (name, value) in enumerate([("FRAME_CONFIG", 2.0), ("ATC_RAT_RLL_P", 0.135), ("ATC_RAT_RLL_P", 0.15)]):
        msg = mavutil.mavlink.MAVLink_param_value_message(name.encode(), value, 9, 3, i)
        out += (1_700_000_000_000_000 + i).to_bytes(8, "big") + msg.pack(mav)
    (tmp_path / "dive.tlog").write_bytes(bytes(out))
    assert ap.read_parameters(tmp_path / "dive.tlog") == {"FRAME_CONFIG": 2.0, "ATC_RAT_RLL_P": pytest.approx(0.15)}


def test_the_stock_parameters_are_those_of_the_real_bluerov2_heavy_log():
    """The shipped stock file's values are the real BlueROV2 Heavy's, as its
    telemetry log carries them (tests/data/logs/ardusub_log_tools, MIT; the
    log stores float32, hence the tolerance)."""
    log = Path(__file__).parents[1] / "data" / "logs" / "ardusub_log_tools" / "bluerov2_heavy_excerpt.tlog"
    stock = ap.read_parameters(Path(neurov.__file__).parent / "vehicles" / "bluerov2_heavy_stock.param")
    real = ap.read_parameters(log)
    assert len(real) == 887 and len(stock) >= 10
    for name, value in stock.items():
        assert real[name] == pytest.approx(value, rel=1e-6), name



def test_identification_reads_a_logs_parameters_with_the_controllers_reader(tmp_path):
    """One reader of a log's parameters (laws.ardusub_params): identification's
    gives the same values and turns its error into identification's LogError."""
    pytest.importorskip("pymavlink")
    from neurov.identification.ardusub_params import read_log_parameters
    from neurov.identification.errors import LogError

    data = Path(__file__).parents[1] / "data" / "logs" / "ardusub_log_tools"
    for log in (data / "bluerov2_heavy_excerpt.tlog", data / "bluerov2_vectored.BIN"):
        assert read_log_parameters(log) == ap.read_log_parameters(log) == ap.read_parameters(log)
    with pytest.raises(LogError, match=r"missing\.bin: no such file"):
        read_log_parameters(tmp_path / "missing.bin")
    with pytest.raises(ap.ArduSubParameterError, match=r"missing\.tlog: no such file"):
        ap.read_log_parameters(tmp_path / "missing.tlog")
