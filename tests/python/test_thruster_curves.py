"""Thruster curves in vehicle files: the shipped T200 curve against the
published points it was built from, its inverse, the BlueROV2 Heavy layout of
the file against the C++ core's, port/starboard names against positions for
every shipped vehicle, named errors for bad curves, and a BlueROV2 run
through its thrusters."""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np
import pytest

from neurov import _core, load_scenario, simulate
from neurov.config.vehicle_file import VehicleFileError, preset_names, preset_path, read_vehicle_file

KGF = 9.80665
# Blue Robotics, T200 Public Performance Data (September 2019), 16 V sheet:
# (PWM us, thrust kgf), the rows the shipped file was built from.
T200_16V = [(1100, -4.07), (1184, -2.94), (1308, -1.35), (1472, 0.0), (1528, 0.0),
            (1624, 0.87), (1728, 2.22), (1840, 4.25), (1864, 4.71), (1900, 5.25)]


def bluerov2() -> dict:
    t = read_vehicle_file(preset_path("bluerov2_heavy")).thrusters
    assert t is not None
    return t


def test_t200_curve_reproduces_the_published_points() -> None:
    t = bluerov2()
    assert t["supply_voltage"] == 16.0
    assert len(t["curves"]) == 8
    for curve in t["curves"]:
        for pwm, kgf in T200_16V:
            assert curve.static_thrust(pwm, 16.0) == pytest.approx(kgf * KGF, rel=1e-12, abs=1e-12)
        # Between rows: linear; inside 1472..1528 us: nothing.
        assert curve.static_thrust(1784.0, 16.0) == pytest.approx((2.22 + 4.25) / 2 * KGF, rel=1e-12)
        assert curve.static_thrust(1500.0, 16.0) == 0.0
        assert curve.static_thrust(1527.0, 16.0) == 0.0
    # Limits default to the curve's ends at the supply voltage: forward 5.25
    # kgf, reverse 4.07 kgf.
    np.testing.assert_allclose(t["max_thrust"], 5.25 * KGF, rtol=1e-12)
    np.testing.assert_allclose(t["min_thrust"], -4.07 * KGF, rtol=1e-12)


def test_t200_inverse_round_trip() -> None:
    curve = bluerov2()["curves"][0]
    for thrust in np.linspace(-4.07 * KGF, 5.25 * KGF, 101):
        if thrust == 0.0:
            continue
        command = curve.command_for(thrust, 16.0)
        assert not 1472.0 < command < 1528.0
        assert curve.static_thrust(command, 16.0) == pytest.approx(thrust, rel=1e-9, abs=1e-9)
    for command in np.linspace(1100.0, 1900.0, 161):
        if 1472.0 <= command <= 1528.0:
            continue
        assert curve.command_for(curve.static_thrust(command, 16.0), 16.0) == pytest.approx(
            command, rel=1e-12)
    # At a lower supply voltage the same thrust needs a larger command.
    assert curve.command_for(30.0, 14.0) > curve.command_for(30.0, 16.0)


def test_bluerov2_file_layout_is_the_cores() -> None:
    positions, directions, names = _core.bluerov2_heavy_layout()
    t = bluerov2()
    expected = np.vstack([directions.T, np.cross(positions, directions).T])
    np.testing.assert_allclose(t["matrix"], expected, rtol=0, atol=1e-15)
    assert [n.replace("_", " ") for n in names] == t["names"]


@pytest.mark.parametrize("name", preset_names())
def test_port_and_starboard_names_match_the_positions(name: str) -> None:
    path = preset_path(name)
    t = read_vehicle_file(path).thrusters
    if t is None:
        pytest.skip(f"{name} has no thrusters")
    assert t["names"] is not None, f"{name}: name the thrusters"
    data = path.read_text()
    rows = re.search(r"^positions = \[(.*?)^\]", data, re.S | re.M)
    assert rows is not None
    positions = np.array([[float(x) for x in r.split(",")]
                          for r in re.findall(r"\[([^\[\]]+)\]", rows.group(1))])
    assert positions.shape == (len(t["names"]), 3)
    for label, (x, y, _) in zip(t["names"], positions):
        words = label.split()
        assert ("starboard" in words) == (y > 0), (name, label, y)
        assert ("port" in words) == (y < 0), (name, label, y)
        if "bow" in words or "forward" in words:
            assert x > 0, (name, label, x)
        if "stern" in words or "aft" in words:
            assert x < 0, (name, label, x)


def _with_curve(tmp_path: Path, curve: str, extra: str = "supply_voltage = 16.0") -> Path:
    base = preset_path("nerov").read_text()
    path = tmp_path / "v.toml"
    path.write_text(base.replace("max_thrust = 250.0   # N, each way\n", extra + "\n")
                    + "\n[thrusters.curve]\n" + curve + "\n")
    return path


GOOD = ("command = [-1.0, -0.1, 0.1, 1.0]\nthrust = [-200.0, 0.0, 0.0, 250.0]\nneutral = 0.0\n"
        "dead_band = 0.1\nreference_voltage = 16.0")


def test_a_curve_file_runs_and_its_limits_are_the_curves(tmp_path: Path) -> None:
    t = read_vehicle_file(_with_curve(tmp_path, GOOD)).thrusters
    assert t is not None
    np.testing.assert_array_equal(t["max_thrust"], np.full(6, 250.0))
    np.testing.assert_array_equal(t["min_thrust"], np.full(6, -200.0))
    half = read_vehicle_file(_with_curve(tmp_path, GOOD, "supply_voltage = 8.0")).thrusters
    assert half is not None
    np.testing.assert_allclose(half["max_thrust"], np.full(6, 250.0 / 4), rtol=1e-15)


@pytest.mark.parametrize(("curve", "extra", "message"), [
    (GOOD.replace("250.0]", "-1.0]"), "supply_voltage = 16.0",
     r"thrusters\.curve\.thrust\[3\] = -1: expected strictly increasing with command outside the "
     r"dead band"),
    (GOOD.replace("[-200.0, 0.0", "[-200.0, -250.0"), "supply_voltage = 16.0",
     r"thrusters\.curve\.thrust\[1\] = -250: expected strictly increasing"),
    (GOOD.replace("[-1.0, -0.1", "[-1.0, -1.0"), "supply_voltage = 16.0",
     r"thrusters\.curve\.command\[1\] = -1: expected strictly increasing"),
    (GOOD, "", r"thrusters\.supply_voltage: expected a number > 0 \(V\) with a curve, got None"),
    (GOOD, "supply_voltage = -3.0", r"thrusters\.supply_voltage: expected a number > 0"),
    (GOOD + "\nslew = 3.0", "supply_voltage = 16.0",
     r"thrusters\.curve\.slew: unknown field; did you mean 'slew_rate'\?"),
    (GOOD.replace("neutral = 0.0\n", ""), "supply_voltage = 16.0",
     r"thrusters\.curve: missing field 'neutral'"),
    (GOOD.replace("250.0]", "250.0, 260.0]"), "supply_voltage = 16.0",
     r"thrusters\.curve\.thrust: expected 4 numbers \(one per command\), got 5"),
    (GOOD + "\nslew_rate = -1.0", "supply_voltage = 16.0",
     r"thrusters\.curve\.slew_rate = -1: expected >= 0"),
    (GOOD, "supply_voltage = 16.0\ntime_constant = 0.1",
     r"thrusters\.time_constant: with a curve the lag is the curve's"),
    (GOOD, "supply_voltage = 16.0\nmax_thrust = 300.0",
     r"thrusters\.max_thrust\[0\] = 300: expected <= the curve's thrust at its highest command"),
])
def test_bad_curves_are_named_errors(tmp_path: Path, curve: str, extra: str, message: str) -> None:
    path = _with_curve(tmp_path, curve, extra)
    with pytest.raises(VehicleFileError, match=re.escape(str(path)) + ".*" + message):
        read_vehicle_file(path)


def test_one_curve_per_thruster_must_be_n_tables(tmp_path: Path) -> None:
    base = preset_path("nerov").read_text().replace("max_thrust = 250.0   # N, each way\n",
                                                    "supply_voltage = 16.0\n")
    path = tmp_path / "v.toml"
    path.write_text(base + ("\n[[thrusters.curve]]\n" + GOOD + "\n") * 5)
    with pytest.raises(VehicleFileError, match=r"thrusters\.curve: expected one table or 6 tables"):
        read_vehicle_file(path)
    path.write_text(base + ("\n[[thrusters.curve]]\n" + GOOD + "\n") * 6)
    t = read_vehicle_file(path).thrusters
    assert t is not None and len(t["curves"]) == 6


def test_bluerov2_scenarios_fly_through_their_thrusters() -> None:
    path = Path(preset_path("bluerov2_heavy")).parents[1] / "scenarios" / "bluerov2_depth_step.toml"
    scenario = load_scenario(path).replace(duration=20.0)
    config = scenario.simulation
    assert config.use_thrusters
    assert len(config.thrusters.curves) == 8
    result = simulate(scenario)
    thrusts = np.asarray(result.thrusts)
    assert thrusts.shape[1] == 8
    assert np.all(thrusts <= 5.25 * KGF + 1e-9)
    assert np.all(thrusts >= -4.07 * KGF - 1e-9)
    assert np.any(np.abs(thrusts) > 1.0)


POLY = "polynomial = [0.0, 100.0, 0.0, 50.0]\ncommand_range = [-1.0, 1.0]\nneutral = 0.0\nreference_voltage = 16.0"


def test_a_polynomial_curve_is_sampled_into_the_table(tmp_path: Path) -> None:
    t = read_vehicle_file(_with_curve(tmp_path, POLY + "\npoints = 201")).thrusters
    assert t is not None
    curve = t["curves"][0]
    assert curve.table.shape == (201, 2)
    # At the sample points (every 0.01) the table is the polynomial 100 c + 50 c^3.
    for c in (-1.0, -0.37, 0.0, 0.25, 0.9, 1.0):
        assert curve.static_thrust(c, 16.0) == pytest.approx(100 * c + 50 * c**3, rel=1e-12, abs=1e-12)
    np.testing.assert_allclose(t["max_thrust"], 150.0, rtol=1e-15)
    np.testing.assert_allclose(t["min_thrust"], -150.0, rtol=1e-15)


@pytest.mark.parametrize(("curve", "message"), [
    ("polynomial = [0.0, 0.0, -1.0]\ncommand_range = [-1.0, 1.0]\nneutral = 0.0\nreference_voltage = 16.0",
     r"thrusters\.curve\.thrust\[\d+\] = .*: expected strictly increasing .*\(the polynomial sampled at "
     r"256 commands over command_range\)"),
    (POLY.replace("command_range = [-1.0, 1.0]", "command_range = [1.0, -1.0]"),
     r"thrusters\.curve\.command_range: expected 2 increasing numbers"),
    (POLY + "\ncommand = [0.0, 1.0]", r"thrusters\.curve\.command: give either 'command' and 'thrust' or"),
    (POLY + "\npoints = 300", r"thrusters\.curve\.points: expected an integer from 2 to 256, got 300"),
    (GOOD + "\npoints = 30", r"thrusters\.curve\.points: only with 'polynomial'"),
    (GOOD.replace("thrust = [-200.0, 0.0, 0.0, 250.0]\n", ""),
     r"thrusters\.curve: missing field 'thrust' \(or give 'polynomial'"),
])
def test_bad_polynomial_curves_are_named_errors(tmp_path: Path, curve: str, message: str) -> None:
    with pytest.raises(VehicleFileError, match=message):
        read_vehicle_file(_with_curve(tmp_path, curve))
