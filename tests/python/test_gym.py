"""neurov.gym.TrackingEnv: the Gymnasium API contract, the action scaling
against independent references, seeding, termination and bad input."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

gymnasium = pytest.importorskip("gymnasium")
from gymnasium.utils.env_checker import check_env  # noqa: E402

import neurov  # noqa: E402
import neurov.gym  # noqa: E402
from neurov import _core  # noqa: E402
from neurov.gym import TrackingEnv, single_dof_limits  # noqa: E402
from neurov.running.plant import build_vehicle, simulation_config  # noqa: E402
from neurov.config.vehicle_file import VehicleFileError, load_limits, load_thrusters, load_vehicle  # noqa: E402

PACKAGE = Path(neurov.__file__).resolve().parent


def test_check_env_passes_in_both_action_modes() -> None:
    check_env(TrackingEnv("paper_fig3"), skip_render_check=True)
    check_env(TrackingEnv("nerov_square_disturbed", action="thrusters"), skip_render_check=True)
    # BlueROV2 Heavy: eight thrusters, one action each (docs/gymnasium.md).
    heavy = TrackingEnv("bluerov2_square", action="thrusters")
    assert heavy.action_space.shape == (8,)
    check_env(heavy, skip_render_check=True)
    check_env(TrackingEnv("bluerov2_square"), skip_render_check=True)


def test_make_after_import_and_in_module_id_form() -> None:
    env = gymnasium.make("neurov/Tracking-v0", scenario="paper_fig3")
    obs, _ = env.reset(seed=0)
    assert obs.shape == (26,)
    # The module:id form imports neurov.gym itself: run it where nothing has.
    code = ("import gymnasium, sys; assert 'neurov.gym' not in sys.modules; "
            "env = gymnasium.make('neurov.gym:neurov/Tracking-v0', scenario='paper_fig3'); "
            "o, _ = env.reset(seed=1); print(o.shape)")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == "(26,)"


def test_single_dof_limits_match_the_inverse_of_a_square_layout() -> None:
    t = load_thrusters(PACKAGE / "vehicles" / "nerov.toml")
    pos, neg = single_dof_limits(t["matrix"], t["min_thrust"], t["max_thrust"])
    # With six independent thrusters u = B^-1 tau is the only way to make tau;
    # the first thruster to reach its limit bounds it.
    binv = np.linalg.inv(t["matrix"])
    expected = 1.0 / np.max(np.abs(binv) / t["max_thrust"][:, None], axis=0)
    np.testing.assert_allclose(pos, expected, rtol=1e-9)
    np.testing.assert_allclose(neg, expected, rtol=1e-9)


def test_single_dof_limits_use_redundant_and_asymmetric_thrusters() -> None:
    # Thrusters 1 and 2 both push in surge (one 40 N forward/-10 N back, one
    # 30 N/-20 N); the rest act alone in one DOF each with +-5.
    matrix = np.zeros((6, 7))
    matrix[0, 0] = matrix[0, 1] = 1.0
    for i in range(1, 6):
        matrix[i, i + 1] = 2.0
    lo = np.array([-10.0, -20.0, -5, -5, -5, -5, -5])
    hi = np.array([40.0, 30.0, 5, 5, 5, 5, 5])
    pos, neg = single_dof_limits(matrix, lo, hi)
    np.testing.assert_allclose(pos, [70.0, 10, 10, 10, 10, 10], rtol=1e-9)
    np.testing.assert_allclose(neg, [30.0, 10, 10, 10, 10, 10], rtol=1e-9)


def test_a_layout_without_a_dof_is_refused() -> None:
    matrix = np.zeros((6, 6))
    matrix[:5, :5] = np.eye(5)
    with pytest.raises(ValueError, match="N \\(yaw moment\\)"):
        single_dof_limits(matrix, -np.ones(6), np.ones(6))


def _direct(scenario: neurov.Scenario, forces: list[np.ndarray], seed: int) -> list[np.ndarray]:
    sim = _core.Simulator(build_vehicle(scenario), simulation_config(scenario))
    sim.reset(seed)
    out = []
    for tau in forces:
        sim.step(tau)
        out.append(np.concatenate(sim.state))
    return out


@pytest.mark.parametrize("action", ["body", "thrusters"])
def test_actions_are_the_scaled_forces_the_simulator_applies(action: str) -> None:
    env = TrackingEnv("nerov_square_disturbed", action=action)
    rng = np.random.default_rng(3)
    actions = [rng.uniform(-1, 1, env.action_space.shape) for _ in range(8)]
    t = load_thrusters(PACKAGE / "vehicles" / "nerov.toml")
    if action == "body":
        pos, _ = single_dof_limits(t["matrix"], t["min_thrust"], t["max_thrust"])
        forces = [a * pos for a in actions]
    else:
        forces = [t["matrix"] @ (a * t["max_thrust"]) for a in actions]
    env.reset(seed=11)
    got = [np.concatenate([info["eta_true"], info["nu_true"]]) for info in (env.step(a)[4] for a in actions)]
    want = _direct(env.scenario, forces, 11)
    np.testing.assert_allclose(np.array(got), np.array(want), rtol=1e-12, atol=1e-12)


def test_same_seed_same_episode_and_another_seed_another() -> None:
    env = TrackingEnv("nerov_square_disturbed")
    actions = np.random.default_rng(5).uniform(-1, 1, (20, 6))

    def episode(seed: int) -> np.ndarray:
        obs, _ = env.reset(seed=seed)
        rows = [obs]
        for a in actions:
            obs, reward, *_ = env.step(a)
            rows.append(np.append(obs, reward))
        return np.concatenate([rows[0], *rows[1:]])

    first, again, other = episode(7), episode(7), episode(8)
    np.testing.assert_array_equal(first, again)
    assert not np.array_equal(first, other)  # the noise is seeded from the seed


def _rotation(phi: float, theta: float, psi: float) -> np.ndarray:
    """Body to NED, R = Rz(psi) Ry(theta) Rx(phi), written out here."""
    rx = np.array([[1, 0, 0], [0, np.cos(phi), -np.sin(phi)], [0, np.sin(phi), np.cos(phi)]])
    ry = np.array([[np.cos(theta), 0, np.sin(theta)], [0, 1, 0], [-np.sin(theta), 0, np.cos(theta)]])
    rz = np.array([[np.cos(psi), -np.sin(psi), 0], [np.sin(psi), np.cos(psi), 0], [0, 0, 1]])
    return rz @ ry @ rx


def test_observation_reward_and_info_from_the_documented_formulas() -> None:
    env = TrackingEnv("paper_fig3", effort_weight=0.5, attitude_weight=2.0)
    env.reset(seed=0)
    for _ in range(30):
        obs, reward, _, _, info = env.step(np.full(6, 0.3))
    eta, nu, eta_d = info["eta"], info["nu"], info["eta_d"]
    o = env.unwrapped._sim.observation
    rot = _rotation(*eta[3:])
    np.testing.assert_allclose(obs[:3], rot.T @ (eta[:3] - eta_d[:3]), rtol=1e-6, atol=1e-6)
    np.testing.assert_allclose(obs[6:12], nu, rtol=1e-6, atol=1e-6)
    np.testing.assert_allclose(obs[12:15], rot.T @ o.eta_d_dot[:3], rtol=1e-6, atol=1e-6)
    np.testing.assert_allclose(obs[3:6], np.angle(np.exp(1j * (eta[3:] - eta_d[3:]))), rtol=1e-6, atol=1e-6)
    np.testing.assert_allclose(obs[24:26], eta[3:5], rtol=1e-6, atol=1e-6)
    e = info["eta_true"] - eta_d
    angles = np.angle(np.exp(1j * e[3:]))  # wrapped to (-pi, pi]
    assert np.any(np.abs(e[3:]) > np.pi)  # the wrap is exercised
    want = -(e[:3] @ e[:3] + 2.0 * angles @ angles + 0.5 * 6 * 0.3**2)
    assert reward == pytest.approx(want, rel=1e-12)
    assert info["action_clips"] == 0


def test_actions_outside_the_space_are_clipped_and_counted() -> None:
    env = TrackingEnv("paper_fig3")
    env.reset(seed=0)
    _, _, _, _, info = env.step(np.array([2.0, 0, 0, 0, 0, -3.0]))
    _, _, _, _, info = env.step(np.zeros(6))
    clipped = info["eta_true"]
    assert info["action_clips"] == 1
    env.reset(seed=0)
    env.step(np.array([1.0, 0, 0, 0, 0, -1.0]))
    _, _, _, _, info = env.step(np.zeros(6))
    np.testing.assert_array_equal(info["eta_true"], clipped)
    assert info["action_clips"] == 0


def test_bad_actions_and_steps_outside_an_episode_raise_and_change_nothing() -> None:
    env = TrackingEnv("paper_fig3")
    with pytest.raises(RuntimeError, match="call reset\\(\\) before step\\(\\)"):
        env.step(np.zeros(6))
    env.reset(seed=0)
    before = env.unwrapped._sim.steps
    with pytest.raises(ValueError, match="'action' must have shape \\(6,\\), got \\(5,\\)"):
        env.step(np.zeros(5))
    with pytest.raises(ValueError, match="'action' must be finite"):
        env.step(np.array([0, 0, np.nan, 0, 0, 0]))
    assert env.unwrapped._sim.steps == before
    with pytest.raises(ValueError, match="'action' must be 'body' or 'thrusters'"):
        TrackingEnv("paper_fig3", action="torque")
    with pytest.raises(ValueError, match="no shipped scenario of that name"):
        TrackingEnv("paper_fig9")


def test_truncated_at_the_duration_then_step_raises(tmp_path: Path) -> None:
    text = (PACKAGE / "scenarios" / "paper_fig3.toml").read_text().replace("duration = 250.0", "duration = 1.0")
    path = tmp_path / "short.toml"
    path.write_text(text)
    env = TrackingEnv(path)
    env.reset(seed=0)
    flags = [env.step(np.zeros(6))[2:4] for _ in range(env.unwrapped._sim.planned_steps)]
    assert flags[-1] == (False, True) and all(f == (False, False) for f in flags[:-1])
    with pytest.raises(RuntimeError, match="the scenario's duration is simulated\\); call reset\\(\\)"):
        env.step(np.zeros(6))


def test_terminated_on_leaving_the_bounding_box() -> None:
    env = TrackingEnv("paper_fig3", box_margin=0.5)
    env.reset(seed=0)
    for k in range(500):
        _, reward, terminated, truncated, info = env.step(-np.eye(6)[0])  # full astern
        if terminated:
            break
    assert terminated and not truncated
    assert info["eta_true"][0] < env.box_low[0]
    e = info["eta_true"] - info["eta_d"]
    angles = np.angle(np.exp(1j * e[3:]))
    left = env.unwrapped._sim.planned_steps - (k + 1)  # k + 1 steps have logged rows 0 .. k
    diagonal = np.linalg.norm(env.box_high - env.box_low)
    want = -(e[:3] @ e[:3] + angles @ angles + 0.01 + diagonal**2 * left)
    assert reward == pytest.approx(want, rel=1e-12)
    with pytest.raises(RuntimeError, match="left the bounding box"):
        env.step(np.zeros(6))


def test_vehicle_limits_table_scales_a_vehicle_without_thrusters(tmp_path: Path) -> None:
    # The BlueROV2 Heavy's parameters without its [thrusters] table.
    body = (PACKAGE / "vehicles" / "bluerov2_heavy.toml").read_text().split("\n[thrusters]")[0]
    body = body[:body.rindex("\n\n")]
    vehicle = tmp_path / "rov.toml"
    vehicle.write_text(body + "\n[limits]\ntau_max = [80, 80, 90, 5, 6, 7]\n")
    (tmp_path / "bare.toml").write_text(body + "\n")
    scenario = (PACKAGE / "scenarios" / "bluerov2_depth_step.toml").read_text().replace(
        'preset = "bluerov2_heavy"', 'file = "rov.toml"').replace("thrusters = true ", "thrusters = false")
    (tmp_path / "s.toml").write_text(scenario)
    (tmp_path / "bare_s.toml").write_text(scenario.replace('file = "rov.toml"', 'file = "bare.toml"'))
    env = TrackingEnv(tmp_path / "s.toml")
    pos, neg = env.action_scale
    np.testing.assert_array_equal(pos, [80, 80, 90, 5, 6, 7])
    np.testing.assert_array_equal(neg, pos)
    check_env(env, skip_render_check=True)
    with pytest.raises(ValueError, match="neither a \\[thrusters\\] table nor \\[limits\\] tau_max"):
        TrackingEnv(tmp_path / "bare_s.toml")
    with pytest.raises(ValueError, match="'thrusters' needs a thruster layout"):
        TrackingEnv(tmp_path / "s.toml", action="thrusters")


def test_limits_table_errors_name_the_field(tmp_path: Path) -> None:
    base = (PACKAGE / "vehicles" / "bluerov2_heavy.toml").read_text()
    for extra, message in (("tau_max = [1, 2, 3]", "limits.tau_max: expected 6 numbers"),
                           ("tau_max = [1, 2, 3, 4, 5, 0]", "expected 6 finite numbers > 0"),
                           ("tau = [1, 2, 3, 4, 5, 6]", "limits.tau: unknown field")):
        path = tmp_path / "v.toml"
        path.write_text(base + "\n[limits]\n" + extra + "\n")
        with pytest.raises(VehicleFileError, match=message):
            load_limits(path)
        with pytest.raises(VehicleFileError, match=message):  # checked whenever the file is read
            load_vehicle(path)
    assert load_limits(PACKAGE / "vehicles" / "nerov.toml") is None


def test_render_rgb_array_draws_the_top_view() -> None:
    env = TrackingEnv("paper_fig3", render_mode="rgb_array")
    env.reset(seed=0)
    for _ in range(20):
        env.step(np.array([0.5, 0.2, 0, 0, 0, 0.1]))
    image = env.render()
    assert image.dtype == np.uint8 and image.shape == (480, 480, 3)
    assert len(np.unique(image.reshape(-1, 3), axis=0)) > 10
    assert TrackingEnv("paper_fig3").render() is None


@pytest.mark.parametrize(
    "action",
    [{"surge": 1.0}, "abcdef", [True] * 6, np.ones(6, dtype=complex), np.zeros(6, dtype=object), ["0"] * 6],
    ids=["dict", "str", "bool", "complex", "object", "numeric strings"],
)
def test_an_action_that_is_not_real_numbers_is_named_and_changes_nothing(action: object) -> None:
    env = TrackingEnv("paper_fig3")
    env.reset(seed=0)
    with pytest.raises(TypeError, match=r"argument 'action' must hold real numbers \(shape \(6,\)\)"):
        env.step(action)
    assert env.unwrapped._sim.steps == 0


def test_render_shows_the_time_and_the_depth() -> None:
    env = TrackingEnv("paper_fig3", render_mode="rgb_array")
    env.reset(seed=0)
    first = env.render()
    for _ in range(15):
        env.step(np.array([0.0, 0.0, 0.3, 0, 0, 0]))  # heave only: the top view hardly moves
    later = env.render()
    assert env.unwrapped._sim.state[0][2] > 0.05
    # The time and depth line above the map, and the depth bar right of it, changed.
    assert not np.array_equal(first[:40], later[:40])
    bar = slice(int(0.80 * 480), int(0.89 * 480))
    assert not np.array_equal(first[:, bar], later[:, bar])


def test_render_before_reset_says_reset_first() -> None:
    env = TrackingEnv("paper_fig3", render_mode="rgb_array")
    with pytest.raises(gymnasium.error.ResetNeeded, match=r"call reset\(\) before render\(\)"):
        env.render()


@pytest.mark.parametrize("seed", [2**63, 2**64, -1])
def test_a_seed_out_of_range_gives_the_range_and_changes_nothing(seed: int) -> None:
    env = TrackingEnv("paper_fig3")
    first, _ = env.reset(seed=3)
    env.step(np.zeros(6))
    if seed == 2**63:  # the core's seeds are 64-bit unsigned: this one is taken
        env.reset(seed=seed)
        return
    with pytest.raises(ValueError, match=r"argument 'seed' must be >= 0 and <= 18446744073709551615"):
        env.reset(seed=seed)
    assert env.unwrapped._sim.steps == 1
