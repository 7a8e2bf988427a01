"""Thrust allocation (neurov._core.allocate_thrust) and thrusters in the closed
loop: allocation, the two saturation modes, failures."""

from __future__ import annotations

import numpy as np
import pytest

from neurov import _core
from neurov.config.scenario import CommandSpec, ControllerSpec, Scenario, ThrusterFailure
from neurov.running.plant import simulation_config
from neurov.running.simulation import simulate
from neurov.config.vehicle_file import load_thrusters, preset_path

NEROV = load_thrusters(preset_path("nerov"))
assert NEROV is not None
B = NEROV["matrix"]
MAX = NEROV["max_thrust"]


def angle(a: np.ndarray, b: np.ndarray) -> float:
    """Angle between two wrenches [rad]; accurate near 0, where arccos of
    the cosine would lose half the digits."""
    ua, ub = a / np.linalg.norm(a), b / np.linalg.norm(b)
    return float(2.0 * np.arctan2(np.linalg.norm(ua - ub), np.linalg.norm(ua + ub)))


# --- allocation ----------------------------------------------------------------------


def test_nerov_layout_is_square_and_full_rank() -> None:
    assert B.shape == (6, 6)
    assert np.linalg.matrix_rank(B) == 6
    np.testing.assert_array_equal(MAX, 250.0)


@pytest.mark.parametrize("saturation", ["scale", "clip"])
def test_allocation_reproduces_tau_when_nothing_saturates(saturation: str, rng: np.random.Generator) -> None:
    for _ in range(20):
        tau = rng.uniform(-1, 1, 6) * np.array([100, 100, 100, 20, 20, 20])
        thrusts, wrench = _core.allocate_thrust(B, tau, MAX, None, saturation)
        assert np.all(np.abs(thrusts) < MAX), "the test's tau must not saturate"
        np.testing.assert_allclose(B @ thrusts, tau, atol=1e-10)
        np.testing.assert_allclose(wrench, tau, atol=1e-10)


def test_redundant_allocation_is_the_least_squares_thrust(rng: np.random.Generator) -> None:
    # Eight thrusters for six DOF: many thrust vectors give tau; the
    # pseudo-inverse picks the one of least norm.
    matrix = rng.normal(size=(6, 8))
    tau = rng.normal(size=6)
    thrusts, wrench = _core.allocate_thrust(matrix, tau)
    np.testing.assert_allclose(wrench, tau, atol=1e-10)
    np.testing.assert_allclose(thrusts, np.linalg.pinv(matrix) @ tau, atol=1e-10)


def test_weights_shift_the_effort(rng: np.random.Generator) -> None:
    matrix = rng.normal(size=(6, 8))
    tau = rng.normal(size=6)
    even, _ = _core.allocate_thrust(matrix, tau)
    weights = np.ones(8)
    weights[0] = 100.0  # thruster 0 is expensive
    weighted, wrench = _core.allocate_thrust(matrix, tau, weights=weights)
    np.testing.assert_allclose(wrench, tau, atol=1e-10)
    assert abs(weighted[0]) < abs(even[0])


# A surge force with a yaw moment: the two aft surge thrusters must differ,
# and the one that must push harder exceeds its limit.
BIG = np.array([1000.0, 0.0, 0.0, 0.0, 0.0, 100.0])


def test_scale_keeps_the_direction_of_the_wrench() -> None:
    thrusts, wrench = _core.allocate_thrust(B, BIG, MAX, None, "scale")
    assert np.all(np.abs(thrusts) <= MAX + 1e-9)
    assert np.max(np.abs(thrusts)) == pytest.approx(250.0)
    assert angle(wrench, BIG) < 1e-9
    assert 0 < np.linalg.norm(wrench) < np.linalg.norm(BIG)
    np.testing.assert_allclose(B @ thrusts, wrench, atol=1e-10)


def test_clip_turns_the_wrench() -> None:
    thrusts, wrench = _core.allocate_thrust(B, BIG, MAX, None, "clip")
    assert np.all(np.abs(thrusts) <= MAX + 1e-9)
    np.testing.assert_allclose(B @ thrusts, wrench, atol=1e-10)
    # Both surge thrusters end at the limit: full surge, but the yaw moment
    # (their difference) is gone.
    np.testing.assert_allclose(thrusts[:2], [250.0, 250.0])
    assert abs(wrench[5]) < 1e-9
    assert np.degrees(angle(wrench, BIG)) > 5.0
    # ... while it delivers more surge force than scaling does.
    _, scaled = _core.allocate_thrust(B, BIG, MAX, None, "scale")
    assert wrench[0] > scaled[0]


@pytest.mark.parametrize("saturation", ["scale", "clip"])
def test_saturated_thrusts_respect_asymmetric_limits(saturation: str, rng: np.random.Generator) -> None:
    low = -0.5 * MAX  # thrusters weaker in reverse
    for _ in range(20):
        tau = rng.normal(size=6) * 2000.0
        thrusts, _ = _core.allocate_thrust(B, tau, MAX, low, saturation)
        assert np.all(thrusts <= MAX + 1e-9) and np.all(thrusts >= low - 1e-9)


def test_bad_allocation_arguments() -> None:
    with pytest.raises(ValueError, match="saturation"):
        _core.allocate_thrust(B, np.zeros(6), MAX, None, "squash")
    with pytest.raises(ValueError, match="rank"):
        _core.allocate_thrust(np.hstack([B[:, :5], B[:, :1]]), np.zeros(6))


# --- in the closed loop ----------------------------------------------------------------


def square_with_thrusters(**changes: object) -> Scenario:
    base = Scenario(
        name="thr", duration=30.0, use_thrusters=True,
        command=CommandSpec(type="square", args={"side": 4.0, "start": 1.0}),
        controller=ControllerSpec(type="pd", kp=np.array([300.0, 300, 300, 100, 100, 100]),
                                  kd=np.array([500.0, 500, 500, 100, 100, 100])),
    )
    return base.replace(**changes)


def test_scenario_passes_the_vehicle_file_thrusters() -> None:
    config = simulation_config(square_with_thrusters(saturation="clip"))
    assert config.use_thrusters
    np.testing.assert_array_equal(config.thrusters.matrix, B)
    assert config.thrusters.saturation == _core.Saturation.clip
    assert not simulation_config(square_with_thrusters(use_thrusters=False)).use_thrusters


def test_unsaturated_thrusters_apply_the_demanded_tau() -> None:
    result = simulate(square_with_thrusters())
    assert result.thrusts.shape == (len(result.t), 6)
    assert np.max(np.abs(result.thrusts)) < 250.0
    assert np.max(np.abs(result.thrusts)) > 1.0
    np.testing.assert_allclose(result.tau_applied, result.tau_demanded, atol=1e-9)


def test_thrusts_column_produces_the_applied_wrench() -> None:
    failure = ThrusterFailure(index=1, efficiency=0.5, time=10.0)
    result = simulate(square_with_thrusters(thruster_failures=[failure], thruster_time_constant=0.5))
    # Both are means over the control interval, and the wrench is linear in
    # the (efficiency-weighted) thrusts, so this holds row by row.
    np.testing.assert_allclose(result.thrusts @ B.T, result.tau_applied, atol=1e-9)
    # The lag makes the applied tau trail the demanded one.
    assert np.max(np.abs(result.tau_applied - result.tau_demanded)) > 1.0


def test_failed_thruster_gives_zero_thrust_after_the_failure() -> None:
    failure = ThrusterFailure(index=0, efficiency=0.0, time=12.0)
    result = simulate(square_with_thrusters(thruster_failures=[failure]))
    after = result.t >= 12.0
    np.testing.assert_array_equal(result.thrusts[after, 0], 0.0)
    # Thruster 0 worked before: the zero afterwards is the failure, not idleness.
    assert np.max(np.abs(result.thrusts[~after, 0])) > 1.0
    # The others keep working.
    assert np.max(np.abs(result.thrusts[after, 1])) > 1.0
    healthy = simulate(square_with_thrusters())
    assert np.max(np.abs(healthy.thrusts[after, 0])) > 1.0


def test_saturating_closed_loop_scale_vs_clip() -> None:
    # Weak thrusters: the demand saturates. 'scale' keeps the applied wrench
    # parallel to the demanded one at every step, 'clip' does not.
    scenario = square_with_thrusters(duration=20.0)

    def run(saturation: str) -> tuple[np.ndarray, np.ndarray]:
        from neurov.laws.registry import build_controller
        from neurov.running.plant import build_vehicle

        config = simulation_config(scenario.replace(saturation=saturation))
        config.thrusters.max_thrust = np.full(6, 5.0)
        config.thrusters.min_thrust = np.full(6, -5.0)
        raw = _core.run_closed_loop(build_vehicle(scenario), build_controller(scenario.controller, scenario),
                                    config)
        return raw["tau_demanded"], raw["tau_applied"]

    demanded, applied = run("scale")
    big = np.linalg.norm(demanded, axis=1) > 1.0
    assert np.count_nonzero(big) > 20
    assert max(angle(a, d) for a, d in zip(applied[big], demanded[big])) < 1e-9
    assert np.max(np.linalg.norm(demanded - applied, axis=1)) > 5.0  # it did saturate
    demanded, applied = run("clip")
    big = np.linalg.norm(demanded, axis=1) > 1.0
    assert max(angle(a, d) for a, d in zip(applied[big], demanded[big])) > np.radians(5.0)


def test_failure_index_out_of_range() -> None:
    with pytest.raises(ValueError, match="thruster_failures.index"):
        simulate(square_with_thrusters(thruster_failures=[ThrusterFailure(index=6, time=1.0)]))
