"""ArduSub's motor stage replayed against real logs (tests/data/logs/
ardusub_log_tools, MIT; docs/ardusub.md, "Replay against real ArduSub
logs"): the pilot's inputs a BlueROV2 Heavy and a BlueROV2 logged, through
the ardusub controller's mixing with the logs' own parameters, give the PWMs
the vehicles sent, to the microsecond."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

pytest.importorskip("pymavlink")

from neurov import ArduSubConfig, ArduSubController  # noqa: E402
from neurov.laws import ardusub_params as ap  # noqa: E402
from neurov.laws.ardusub_replay import MANUAL, replay_mixing  # noqa: E402

DATA = Path(__file__).resolve().parents[1] / "data" / "logs" / "ardusub_log_tools"


def test_the_heavys_pilot_inputs_give_its_logged_pwms():
    r = replay_mixing(DATA / "bluerov2_heavy_rc_servo.tlog", DATA / "bluerov2_heavy_excerpt.tlog")
    assert r.frame == 2 and r.modes == {MANUAL} and r.logged.shape == (32, 8)
    # Real inputs: half forward and half up at their largest.
    assert np.abs(r.inputs).max(axis=0)[[3, 4]] == pytest.approx([0.5, 0.5])
    within = np.all(np.abs(r.error) <= 1.0, axis=1)
    assert within.sum() == 31
    # The one other sample is the last: the vehicle disarming, every motor already at neutral.
    assert not within[-1] and np.all(r.logged[-1] == 1500)


def test_the_bluerov2s_pilot_inputs_give_its_logged_pwms():
    r = replay_mixing(DATA / "bluerov2_vectored.BIN")
    assert r.frame == 1 and r.modes == {MANUAL} and r.logged.shape == (87, 6)
    within = np.all(np.abs(r.error) <= 1.0, axis=1)
    assert within.sum() == 82
    # The five others: the first half second of the log, the motors held at neutral while they
    # spool up after arming (MOT_SPOOL_TIME 0.5 s), which the model does not have.
    assert np.all(~within[:5]) and np.all(r.logged[:5] == 1500) and r.t[4] - r.t[0] < 0.5


def test_mix_is_the_motor_stage_alone():
    c = ArduSubConfig()
    c.FRAME_CONFIG = 2
    c.MOT_1_DIRECTION = -1.0
    mixer = ArduSubController(c)
    # A pure heave up lights the four vertical motors alike; a reversed motor's PWM mirrors.
    assert mixer.mix(np.array([0, 0, 0, 0.5, 0, 0])) == pytest.approx([1500] * 4 + [1300] * 4)
    assert mixer.mix(np.array([0, 0, 0, 0, 0.5, 0]))[:4] == pytest.approx([1700, 1300, 1700, 1700])
    # Inputs held within -1..1, PWMs within MOT_PWM_MIN/MAX.
    assert mixer.mix(np.array([0, 0, 0, 5.0, 0, 0])) == pytest.approx(mixer.mix(np.array([0, 0, 0, 1.0, 0, 0])))


def test_a_log_without_parameters_is_named(tmp_path):
    mavutil = pytest.importorskip("pymavlink.mavutil")
    mav = mavutil.mavlink.MAVLink(None, srcSystem=1, srcComponent=1)
    msg = mavutil.mavlink.MAVLink_heartbeat_message(12, 3, 0, 19, 4, 3)
    (tmp_path / "dive.tlog").write_bytes((1_700_000_000_000_000).to_bytes(8, "big") + msg.pack(mav))
    with pytest.raises(ap.ArduSubParameterError, match=r"dive\.tlog: the log holds no parameters"):
        replay_mixing(tmp_path / "dive.tlog")
