"""The tether (sim/disturbances/tether.hpp): the [tether] table of a scenario
file, the closed form of a vertical line in a uniform current, its moment and
frame, and its errors named by file and TOML key."""

from __future__ import annotations

import copy
import sys

import numpy as np
import pytest

from neurov.config.scenario import ControllerSpec, ScenarioError
from neurov.config.reading import read_scenario, scenario_from_mapping
from neurov.running.simulation import simulate
from neurov.study.spec import SCENARIO_DIR

if sys.version_info >= (3, 11):
    import tomllib
else:  # pragma: no cover
    import tomli as tomllib

BASE = tomllib.loads((SCENARIO_DIR / "nerov_square.toml").read_text())
RHO, CD, D = 1025.0, 1.2, 0.0076


def still(tether: dict, *, depth: float = 20.0, current=(0.5, 0.0, 0.0), yaw: float = 0.0,
          **tables: object):
    """A vehicle held at (0, 0, depth) with `yaw` for 0.2 s: row 0 is its pose."""
    data = copy.deepcopy(BASE)
    data.update({"duration": 0.2, "initial": {"eta": [0, 0, depth, 0, 0, yaw]},
                 "command": {"type": "waypoints", "times": [0.0], "poses": [[0, 0, depth, 0, 0, yaw]]},
                 "current": {"velocity": list(current)}, "tether": tether})
    data.pop("disturbances", None)
    data["controller"] = {"type": "pd"}  # the force does not matter at row 0; PD builds fastest
    data.update(copy.deepcopy(tables))
    return scenario_from_mapping(data, "tether.toml")


def force_at_start(s) -> np.ndarray:
    return simulate(s).disturbance[0]


def test_vertical_tether_in_a_uniform_current_gives_the_closed_form() -> None:
    # F = 1/4 rho C_d d L U^2 along the current: half of the line's drag.
    for length, u in ((20.0, 0.5), (7.5, 1.3)):
        f = force_at_start(still({"diameter": D, "drag_coefficient": CD}, depth=length, current=(u, 0, 0)))
        expected = 0.25 * RHO * CD * D * length * u**2
        assert f[0] == pytest.approx(expected, rel=1e-12)
        np.testing.assert_allclose(f[1:], 0.0, atol=1e-12 * expected)


def test_the_moment_is_the_force_at_the_attachment_and_the_force_is_in_body_axes() -> None:
    # The line stays vertical: anchor above the attachment point 0.1 m ahead, 0.2 m up.
    t = {"diameter": D, "anchor": [0.1, 0.0, 0.0], "attachment": [0.1, 0.0, -0.2]}
    f = force_at_start(still(t, depth=10.2))
    fx = 0.25 * RHO * CD * D * 10.0 * 0.25
    np.testing.assert_allclose(f, [fx, 0, 0, 0, -0.2 * fx, 0], rtol=1e-12, atol=1e-12 * fx)
    # Facing east, the northward drag pushes the vehicle to its left (body -y).
    f = force_at_start(still({"diameter": D}, depth=10.0, yaw=np.pi / 2))
    np.testing.assert_allclose(f, [0, -fx, 0, 0, 0, 0], rtol=1e-12, atol=1e-12 * fx)


def test_only_the_flow_normal_to_the_line_drags() -> None:
    along = force_at_start(still({"diameter": D}, current=(0.0, 0.0, 0.5)))
    np.testing.assert_allclose(along, 0.0, atol=1e-15)
    # A line at 45 deg in the north-down plane: |u_n| = U / sqrt 2, normal to the line.
    f = force_at_start(still({"diameter": D, "anchor": [-10.0, 0.0, 0.0]}, depth=10.0))
    length, un = np.sqrt(200.0), 0.5 / np.sqrt(2.0)
    magnitude = 0.25 * RHO * CD * D * length * un**2
    np.testing.assert_allclose(f[:3], magnitude * np.array([1.0, 0.0, -1.0]) / np.sqrt(2.0), rtol=1e-12)


def test_waves_add_their_orbital_flow_along_the_line() -> None:
    waves = {"hs": 1.5, "tp": 7.0, "components": 50}
    calm = simulate(still({"diameter": D}, depth=8.0, duration=5.0))
    sea = simulate(still({"diameter": D}, depth=8.0, duration=5.0, waves=waves))
    assert np.isfinite(sea.disturbance).all()
    assert np.abs(sea.disturbance - calm.disturbance)[:, :3].max() > 0.01 * np.abs(calm.disturbance).max()


def test_bad_tables_are_named_by_key() -> None:
    cases = [
        ({}, "tether.toml: tether.diameter = 0: expected > 0 and finite"),
        ({"diameter": D, "drag_coefficient": -1.0}, "tether.toml: tether.drag_coefficient = -1: expected >= 0"),
        ({"diameter": D, "length": 19.0}, "tether.toml: tether.length = 19: expected >= the straight distance"),
        ({"diameter": D, "diamter": 1.0}, "tether.toml: tether.diamter: unknown field"),
        ({"diameter": D, "anchor": [0.0, 0.0]}, "tether.toml: tether.anchor: expected 3 numbers"),
    ]
    for table, message in cases:
        with pytest.raises(ScenarioError) as e:
            still(table)
        assert str(e.value).startswith(message), str(e.value)
    # Slack is allowed (and not modelled): a longer cable gives the same force.
    assert force_at_start(still({"diameter": D, "length": 30.0}))[0] == force_at_start(still({"diameter": D}))[0]


def test_the_shipped_bluerov2_tether_scenario_pulls_as_its_straight_line_does() -> None:
    s = read_scenario(SCENARIO_DIR / "bluerov2_square_tether.toml")
    t, c = s.simulation.tether, s.simulation
    assert not np.any(c.eta0[3:]) and c.current_model.name == "constant"
    # At t = 0 (body axes = NED, the yaw disturbance's sine at 0) the line is
    # straight in a uniform current: F = 1/4 rho C_d d L |u_n| u_n.
    line = c.eta0[:3] + t.attachment - t.anchor
    length = np.linalg.norm(line)
    e = line / length
    un = c.current - (c.current @ e) * e
    f = 0.25 * c.water_density * t.drag_coefficient * t.diameter * length * np.linalg.norm(un) * un
    r = simulate(s.replace(duration=0.2, controller=ControllerSpec(type="pd")))
    np.testing.assert_allclose(r.disturbance[0], [*f, *np.cross(t.attachment, f)], rtol=1e-12, atol=1e-15)
    assert np.linalg.norm(f) > 0.5  # N


def test_a_run_without_a_tether_describes_itself_as_before_tethers() -> None:
    """Study fingerprints hash Scenario.describe(): a tether-less scenario's
    must not name the tether, so that its study folders stay its own."""
    plain = read_scenario(SCENARIO_DIR / "bluerov2_square.toml").describe()["simulation"]
    tethered = read_scenario(SCENARIO_DIR / "bluerov2_square_tether.toml").describe()["simulation"]
    assert "tether" not in plain
    assert tethered["tether"]["diameter"] > 0
