"""The compiled tracking task (neurov._core.TrackingTask, what both Gymnasium
envs step through) against the documented formulas written here in numpy:
the observation (body-frame errors, wrapped angles near +-pi, a dropout's
NaN read as 0, the bounds), the reward and the episode's end (rows outside
the box, diverged and done rows), and the action's force with symmetric and
asymmetric limits, with and without a thruster matrix."""

from __future__ import annotations

import numpy as np
import pytest

from neurov import _core

PI = np.pi


# --- the formulas of docs/gymnasium.md, in numpy ---------------------------------------------------------

def wrap(x: np.ndarray) -> np.ndarray:
    return x - np.rint(x / (2 * PI)) * (2 * PI)


def rotation(phi: float, theta: float, psi: float) -> np.ndarray:
    """Body to NED, R = Rz(psi) Ry(theta) Rx(phi)."""
    rx = np.array([[1, 0, 0], [0, np.cos(phi), -np.sin(phi)], [0, np.sin(phi), np.cos(phi)]])
    ry = np.array([[np.cos(theta), 0, np.sin(theta)], [0, 1, 0], [-np.sin(theta), 0, np.cos(theta)]])
    rz = np.array([[np.cos(psi), -np.sin(psi), 0], [np.sin(psi), np.cos(psi), 0], [0, 0, 1]])
    return rz @ ry @ rx


def attitude_inverse(phi: float, theta: float) -> np.ndarray:
    """T(Theta)^-1: the Euler-angle rates to the body rates (Fossen 2011, 2.29)."""
    sp, cp, st, ct = np.sin(phi), np.cos(phi), np.sin(theta), np.cos(theta)
    return np.array([[1, 0, -st], [0, cp, ct * sp], [0, -sp, ct * cp]])


def body(eta: np.ndarray, v: np.ndarray) -> np.ndarray:
    """J(eta)^-1 v."""
    return np.concatenate([rotation(*eta[3:]).T @ v[:3], attitude_inverse(*eta[3:5]) @ v[3:]])


def observation(eta, nu, eta_d, eta_d_dot, eta_d_ddot, high, dropouts_read_zero):
    rows = []
    for e, n, d, dd, ddd in zip(eta, nu, eta_d, eta_d_dot, eta_d_ddot):
        if dropouts_read_zero:
            e, n = np.where(np.isfinite(e), e, 0.0), np.where(np.isfinite(n), n, 0.0)
        rot = rotation(*e[3:])
        rows.append(np.concatenate([rot.T @ (e[:3] - d[:3]), wrap(e[3:] - d[3:]), n, body(e, dd), body(e, ddd),
                                    e[3:5]]))
    with np.errstate(over="ignore"):  # a number beyond float32 casts to inf, then clipped
        return np.clip(np.array(rows).astype(np.float32), -high, high)


def score(eta_true, eta_d, actions, diverged, done, steps_left, weights, low, high, cost):
    dp = eta_true[:, :3] - eta_d[:, :3]
    da = wrap(eta_true[:, 3:] - eta_d[:, 3:])
    pw, aw, ew = weights
    reward = -(pw * (dp**2).sum(1) + aw * (da**2).sum(1) + ew * (actions**2).sum(1))
    p = eta_true[:, :3]
    outside = ~((p >= low) & (p <= high)).all(axis=1)
    terminated = outside | diverged
    reward = np.where(terminated, reward - cost * steps_left, reward)
    return reward, terminated, done & ~terminated, outside


def forces(actions, pos, neg, matrix):
    u = actions * np.where(actions >= 0, pos, neg)
    return u if matrix is None else u @ matrix.T


# --- the rows ------------------------------------------------------------------------------------------

LOW, HIGH = np.array([-10.0, -20.0, -3.0]), np.array([30.0, 15.0, 8.0])
WEIGHTS = (1.5, 2.0, 0.05)


def _task(pos=None, neg=None, matrix=None, dropouts_read_zero=False) -> _core.TrackingTask:
    n = 6 if matrix is None else matrix.shape[1]
    config = _core.TrackingTaskConfig(
        position_weight=WEIGHTS[0], attitude_weight=WEIGHTS[1], effort_weight=WEIGHTS[2], box_low=LOW,
        box_high=HIGH, velocity_bound=2.5, action_positive=np.ones(n) if pos is None else pos,
        action_negative=np.ones(n) if neg is None else neg,
        thrusters=np.zeros((6, 0)) if matrix is None else matrix, dropouts_read_zero=dropouts_read_zero)
    return _core.TrackingTask(config)


def _rows(k: int, seed: int = 3) -> dict[str, np.ndarray]:
    rng = np.random.default_rng(seed)
    r = {name: rng.uniform(-7.0, 7.0, (k, 6)) for name in ("eta", "nu", "eta_d", "eta_d_dot", "eta_d_ddot")}
    r["eta"][:, :3] = rng.uniform(-2.5, 2.5, (k, 3))  # inside the box (also after eta_true's noise)
    r["eta"][:, 4] = rng.uniform(-1.4, 1.4, k)  # pitch away from the singularity
    r["eta_true"] = r["eta"] + rng.normal(0, 0.1, (k, 6))
    # Angle errors at and near +-pi, and a multiple of it: the wrap's edges (a tie rounds to even).
    edges = np.array([PI, -PI, 3 * PI, PI - 1e-12, PI + 1e-12, -PI - 1e-12, -PI + 1e-12, 5 * PI + 1e-9])
    for j, e in enumerate(edges[:k]):
        r["eta"][j, 3 + j % 3] = r["eta_d"][j, 3 + j % 3] + e
        r["eta_true"][j, 3 + (j + 1) % 3] = r["eta_d"][j, 3 + (j + 1) % 3] + e
    return r


def _flags(k: int, eta_true: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    diverged = np.zeros(k, dtype=bool)
    done = np.zeros(k, dtype=bool)
    eta_true[10, 0] = HIGH[0] + 0.1  # outside in x, y, z; NaN is outside
    eta_true[11, 1] = LOW[1] - 1e-9
    eta_true[12, 2] = HIGH[2] * 1.5
    eta_true[13, :3] = np.nan
    diverged[14] = diverged[13] = True  # diverged inside the box, and outside
    done[14] = done[15] = done[16] = True  # done and diverged: terminated, not truncated
    eta_true[16, 0] = LOW[0] - 2.0
    steps_left = np.arange(k, dtype=np.int64) * 7
    return diverged, done, steps_left


def test_the_observation_is_the_formula_with_wrapped_angles_and_its_bounds() -> None:
    task = _task()
    r = _rows(40)
    r["nu"][20, 0] = 1e300  # beyond float32 and the bound: clipped, not inf
    got = task.observe_rows(r["eta"], r["nu"], r["eta_d"], r["eta_d_dot"], r["eta_d_ddot"])
    high = task.observation_high
    want = observation(r["eta"], r["nu"], r["eta_d"], r["eta_d_dot"], r["eta_d_ddot"], high, False)
    assert got.dtype == np.float32 and got.shape == (40, 26)
    np.testing.assert_array_max_ulp(got, want, maxulp=1)
    assert np.abs(got).max() <= high.max() and got[20, 6] == high[6] == np.float32(2.5)
    assert (np.abs(got[:, 3:6]) <= np.float32(PI)).all()
    np.testing.assert_array_equal(high, np.float32([task.reach] * 3 + [PI] * 3 + [2.5] * 18 + [PI] * 2))
    assert task.reach == pytest.approx(np.linalg.norm(HIGH - LOW), rel=1e-15)


def test_a_dropouts_nan_reads_zero_only_when_the_task_says_so() -> None:
    r = _rows(12)
    r["eta"][1, 2] = r["eta"][2, 5] = r["nu"][3, :] = np.nan
    r["eta"][4, 0] = np.inf
    args = (r["eta"], r["nu"], r["eta_d"], r["eta_d_dot"], r["eta_d_ddot"])
    zero = _task(dropouts_read_zero=True)
    got = zero.observe_rows(*args)
    assert np.isfinite(got).all()
    np.testing.assert_array_max_ulp(got, observation(*args, zero.observation_high, True), maxulp=1)
    np.testing.assert_array_equal(got[3, 6:12], 0.0)
    kept = _task().observe_rows(*args)  # no sensor faults configured: a NaN shows
    assert np.isnan(kept[3, 6:12]).all() and np.isfinite(kept[5]).all()


def test_reward_and_episode_end_are_the_formula_outside_the_box_and_diverged() -> None:
    task = _task()
    k = 24
    r = _rows(k)
    diverged, done, steps_left = _flags(k, r["eta_true"])
    actions = np.random.default_rng(5).uniform(-1, 1, (k, 6))
    got = task.score_rows(r["eta_true"], r["eta_d"], actions, diverged, done, steps_left)
    cost = WEIGHTS[0] * np.linalg.norm(HIGH - LOW) ** 2
    want = score(r["eta_true"], r["eta_d"], actions, diverged, done, steps_left, WEIGHTS, LOW, HIGH, cost)
    assert task.termination_cost == pytest.approx(cost, rel=1e-14)
    finite = np.isfinite(want[0])
    np.testing.assert_allclose(got[0][finite], want[0][finite], rtol=1e-12, atol=0)
    assert np.isnan(got[0][13]) and finite.sum() == k - 1  # a NaN position: NaN reward, outside
    for g, w in zip(got[1:], want[1:], strict=True):
        np.testing.assert_array_equal(g, w)
    terminated, truncated, outside = got[1:]
    np.testing.assert_array_equal(np.flatnonzero(outside), [10, 11, 12, 13, 16])
    np.testing.assert_array_equal(np.flatnonzero(terminated), [10, 11, 12, 13, 14, 16])
    np.testing.assert_array_equal(np.flatnonzero(truncated), [15])
    # A terminated row pays for each step not simulated.
    assert got[0][10] < -cost * steps_left[10]


@pytest.mark.parametrize("layout", ["body symmetric", "body asymmetric", "thrusters asymmetric"])
def test_the_force_of_an_action_is_the_scaled_limits_through_the_thrusters(layout: str) -> None:
    rng = np.random.default_rng(9)
    matrix = rng.normal(0, 1, (6, 8)) if layout.startswith("thrusters") else None
    n = 6 if matrix is None else 8
    pos = rng.uniform(5, 50, n)
    neg = pos if layout.endswith(" symmetric") else rng.uniform(1, 20, n)
    task = _task(pos, neg, matrix)
    actions = rng.uniform(-1, 1, (30, n))
    actions[0] = 0.0
    actions[1] = -1.0
    actions[2] = 1.0
    got = task.forces(actions)
    np.testing.assert_allclose(got, forces(actions, pos, neg, matrix), rtol=1e-12, atol=1e-12)
    if layout == "body asymmetric":
        np.testing.assert_array_equal(got[1], -neg)
        np.testing.assert_array_equal(got[2], pos)


def test_clip_bounds_the_actions_and_names_a_non_finite_row() -> None:
    task = _task()
    a = np.array([[0.5, -0.5, 0, 0, 0, 1.0], [2.0, 0, 0, 0, 0, -3.0], [0.1] * 6])
    clipped, rows = task.clip(a)
    np.testing.assert_array_equal(clipped, np.clip(a, -1, 1))
    np.testing.assert_array_equal(rows, [False, True, False])
    a[2, 3] = np.nan
    a[0, 0] = np.inf
    with pytest.raises(ValueError, match=r"argument 'actions' must be finite, got \[inf, .*\] in row 0 "
                                         r"\(rows \[0, 2\] are not\)"):
        task.clip(a)


def test_arguments_and_constants_are_checked_naming_them() -> None:
    task = _task()
    r = _rows(3)
    with pytest.raises(ValueError, match=r"argument 'nu' must have shape \(3, 6\), got \(2, 6\)"):
        task.observe_rows(r["eta"], r["nu"][:2], r["eta_d"], r["eta_d_dot"], r["eta_d_ddot"])
    with pytest.raises(TypeError, match="argument 'diverged' must be a bool array of shape"):
        task.score_rows(r["eta_true"], r["eta_d"], np.zeros((3, 6)), np.zeros(3), np.zeros(3, bool), np.zeros(3))
    with pytest.raises(ValueError, match=r"argument 'actions' must have shape \(3, 6\)"):
        task.score_rows(r["eta_true"], r["eta_d"], np.zeros((3, 5)), np.zeros(3, bool), np.zeros(3, bool),
                        np.zeros(3, dtype=np.int64))
    with pytest.raises(TypeError, match="argument 'actions' must hold real numbers"):
        task.forces(np.zeros((2, 6), dtype=bool))
    for fields, message in (({"box_low": HIGH}, "box_high.*> box_low"),
                            ({"action_negative": np.ones(5)}, "action_negative.*as many components"),
                            ({"action_positive": np.ones(8), "action_negative": np.ones(8)}, "6 components"),
                            ({"action_positive": np.ones(8), "action_negative": np.ones(8),
                              "thrusters": np.ones((6, 7))}, "thrusters.*one column per action"),
                            ({"action_positive": [1, 1, 0, 1, 1, 1]}, r"action_positive\[2\] = 0"),
                            ({"effort_weight": -1.0}, "effort_weight = -1: expected >= 0"),
                            ({"velocity_bound": 0.0}, "velocity_bound = 0")):
        with pytest.raises(_core.ValidationError, match=message):
            _core.TrackingTask(_core.TrackingTaskConfig(**{"box_low": LOW, "box_high": HIGH, **fields}))


def test_one_batch_step_is_the_row_functions_over_its_lanes() -> None:
    # step_batch (the vector env's one call) against clip, forces, BatchSimulator.step and the row functions.
    pytest.importorskip("gymnasium")
    from neurov.gym import TrackingEnv
    from neurov.running.plant import build_vehicle, simulation_config

    env = TrackingEnv("nerov_square_disturbed", action="thrusters")
    task = env.task.core
    k = 4
    make = lambda: _core.BatchSimulator([build_vehicle(env.scenario)] * k, [simulation_config(env.scenario)] * k)  # noqa: E731
    one, other = make(), make()
    seeds = np.arange(k, dtype=np.uint64) + 3
    one.reset(seeds)
    other.reset(seeds)
    mask = np.array([True, False, True, True])
    actions = np.random.default_rng(2).uniform(-1.5, 1.5, (k, task.action_size))
    obs, reward, terminated, truncated, info, clipped, outside = task.step_batch(one, actions, mask)
    a, want_clipped = task.clip(actions)
    statuses = other.step(task.forces(a), mask)
    o = other.observation
    eta_true, _ = other.state
    np.testing.assert_array_equal(info["plant_status"], statuses)
    np.testing.assert_array_equal(clipped, want_clipped)
    np.testing.assert_array_equal(obs, task.observe_rows(o["eta"], o["nu"], o["eta_d"], o["eta_d_dot"],
                                                         o["eta_d_ddot"]))
    np.testing.assert_array_equal(info["eta_true"], eta_true)
    r, te, tr, out = task.score_rows(eta_true, o["eta_d"], a, other.diverged, other.done,
                                     other.planned_steps - other.steps)
    r[~mask] = 0.0
    np.testing.assert_array_equal(reward, r)
    np.testing.assert_array_equal(terminated, te & mask)
    np.testing.assert_array_equal(outside, out & mask)
    assert not truncated.any()
    with pytest.raises(ValueError, match="row 1"):
        bad = np.zeros((k, task.action_size))
        bad[1, 0] = np.nan
        task.step_batch(one, bad)
    np.testing.assert_array_equal(one.steps, [1, 0, 1, 1])  # the refused call stepped nothing


def test_returned_arrays_are_not_the_reused_buffers() -> None:
    pytest.importorskip("gymnasium")
    from neurov.gym import TrackingEnv

    env = TrackingEnv("paper_fig3")
    obs0, _ = env.reset(seed=0)
    first = env.step(np.full(6, 0.5, dtype=np.float32))
    kept = [obs0.copy(), first[0].copy()]
    for _ in range(3):
        env.step(np.full(6, -0.5, dtype=np.float32))
    np.testing.assert_array_equal(obs0, kept[0])
    np.testing.assert_array_equal(first[0], kept[1])
