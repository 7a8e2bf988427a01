"""neurov.gym.TrackingVectorEnv: the vector contract gymnasium has no checker
for (spaces, shapes and dtypes, autoreset in each mode, seeding, info
arrays, closing), lane i against the single env under seed s + i, and the
per-episode domain randomisation."""

from __future__ import annotations

import os
import subprocess
import sys
import textwrap
from typing import Any

import numpy as np
import pytest

gymnasium = pytest.importorskip("gymnasium")
import neurov  # noqa: E402
import neurov.gym  # noqa: E402
from neurov import _core  # noqa: E402
from gymnasium.utils.env_checker import check_env  # noqa: E402
from gymnasium.vector import AutoresetMode, VectorEnv  # noqa: E402
from neurov.running.lanes import PythonLanes  # noqa: E402
from neurov.gym import TrackingEnv, TrackingVectorEnv, resolve_scenario  # noqa: E402

# Short episodes (7 steps: t = 0.2 .. 1.4 s) so that the tests cross autoresets.
SHORT = {"duration": 1.2}
RANDOMIZE = [{"parameter": "mass", "relative": 0.3},
             {"parameter": "linear_damping", "relative": 0.2, "distribution": "normal"},
             {"parameter": "current_speed", "range": [0.0, 0.5]},
             {"parameter": "current_direction", "range": [0.0, 360.0]},
             {"parameter": "noise_scale", "range": [0.5, 2.0]}]


def _scenario(name: str = "paper_fig3") -> neurov.Scenario:
    return resolve_scenario(name).replace(**SHORT)


def test_make_vec_gives_a_vector_env_with_batched_spaces() -> None:
    envs = gymnasium.make_vec("neurov/Tracking-v0", num_envs=3, vectorization_mode="vector_entry_point",
                              scenario="paper_fig3")
    assert isinstance(envs, VectorEnv) and envs.num_envs == 3
    assert envs.metadata["autoreset_mode"] == AutoresetMode.NEXT_STEP
    assert envs.single_observation_space.shape == (26,) and envs.single_action_space.shape == (6,)
    assert envs.observation_space.shape == (3, 26) and envs.observation_space.dtype == np.float32
    assert envs.action_space.shape == (3, 6) and envs.action_space.dtype == np.float32
    obs, info = envs.reset(seed=0)
    assert obs.shape == (3, 26) and obs.dtype == np.float32 and envs.observation_space.contains(obs)
    obs, reward, terminated, truncated, info = envs.step(envs.action_space.sample())
    assert obs.dtype == np.float32 and envs.observation_space.contains(obs)
    assert reward.shape == (3,) and reward.dtype == np.float64
    assert terminated.dtype == truncated.dtype == np.bool_ and terminated.shape == truncated.shape == (3,)
    # info: gymnasium's vector convention, each key an array of K rows with its mask _key.
    for key, shape in (("t", (3,)), ("eta", (3, 6)), ("eta_true", (3, 6)), ("action_clips", (3,)),
                       ("plant_status", (3,))):
        assert info[key].shape == shape and info[f"_{key}"].dtype == np.bool_ and info[f"_{key}"].all()
    envs.close()


def _single_run(scenario: neurov.Scenario, seed: int, actions: np.ndarray, action: str,
                randomize: Any, **task: Any) -> list[tuple[Any, ...]]:
    """What the single env gives for one lane's actions under NEXT_STEP: a
    step after an episode's end is its reset (obs, reward 0)."""
    env = TrackingEnv(scenario, action=action, randomize=randomize, **task)
    obs, _ = env.reset(seed=seed)
    out, ended = [], False
    for a in actions:
        if ended:
            obs, info = env.reset()
            out.append((obs, 0.0, False, False, info["eta_true"]))
            ended = False
            continue
        obs, r, term, trunc, info = env.step(a)
        out.append((obs, r, term, trunc, info["eta_true"]))
        ended = term or trunc
    return out


@pytest.mark.parametrize("batch_class", [None, PythonLanes])  # the compiled batch, the reference
@pytest.mark.parametrize(("name", "action", "randomize"), [("paper_fig3", "body", None),
                                                           ("nerov_square_disturbed", "thrusters", RANDOMIZE)])
def test_lane_i_is_the_single_env_under_seed_s_plus_i(name: str, action: str, randomize: Any,
                                                      batch_class: Any) -> None:
    scenario = _scenario(name)
    k, steps = 3, 16  # crosses two autoresets
    envs = TrackingVectorEnv(k, scenario, action, randomize=randomize, batch_class=batch_class)
    envs.reset(seed=40)
    rng = np.random.default_rng(1)
    actions = rng.uniform(-1.2, 1.2, (steps, *envs.action_space.shape))  # some clipped
    got = [envs.step(a) for a in actions]
    assert any(g[3].any() for g in got)
    for i in range(k):
        want = _single_run(scenario, 40 + i, actions[:, i], action, randomize)
        for (obs, r, term, trunc, info), (w_obs, w_r, w_term, w_trunc, w_eta) in zip(got, want):
            np.testing.assert_allclose(obs[i], w_obs, rtol=1e-6, atol=1e-7)
            np.testing.assert_allclose(r[i], w_r, rtol=1e-12, atol=1e-12)
            np.testing.assert_allclose(info["eta_true"][i], w_eta, rtol=1e-12, atol=1e-12)
            assert (term[i], trunc[i]) == (w_term, w_trunc)


@pytest.mark.parametrize("batch_class", [None, PythonLanes])
def test_lane_i_is_the_single_env_across_terminations(batch_class: Any) -> None:
    """A tight speed bound and box: episodes end terminated, each lane at its
    own step, and every lane still steps as the single env under seed s + i."""
    scenario = _scenario("nerov_square_disturbed")
    task = {"velocity_bound": 0.05, "box_margin": 0.1}
    k, steps = 4, 24
    envs = TrackingVectorEnv(k, scenario, "body", randomize=RANDOMIZE, batch_class=batch_class, **task)
    envs.reset(seed=7)
    actions = np.random.default_rng(3).uniform(-1.0, 1.0, (steps, *envs.action_space.shape))
    got = [envs.step(a) for a in actions]
    ends = np.array([g[2] for g in got])
    assert ends.sum() >= k and len({int(np.argmax(ends[:, i])) for i in range(k)}) > 1
    for i in range(k):
        want = _single_run(scenario, 7 + i, actions[:, i], "body", RANDOMIZE, **task)
        for (obs, r, term, trunc, info), (w_obs, w_r, w_term, w_trunc, w_eta) in zip(got, want):
            np.testing.assert_allclose(obs[i], w_obs, rtol=1e-6, atol=1e-7)
            np.testing.assert_allclose(r[i], w_r, rtol=1e-12, atol=1e-12)
            np.testing.assert_allclose(info["eta_true"][i], w_eta, rtol=1e-12, atol=1e-12)
            assert (term[i], trunc[i]) == (w_term, w_trunc)


def test_the_lanes_split_over_threads_give_one_thread_s_steps() -> None:
    """Three shares of envs stepped on 1 thread, on 2 (the module's kept
    threads) and on 3 (threads started for the call): every array the same
    to the bit, across autoresets."""
    scenario = _scenario("nerov_square_disturbed")
    runs = []
    for threads in (1, 2, 3):
        envs = TrackingVectorEnv(3 * _core.MIN_LANES_PER_THREAD, scenario, "thrusters", threads=threads)
        envs.reset(seed=3)
        actions = np.random.default_rng(4).uniform(-1.2, 1.2, (16, *envs.action_space.shape))
        runs.append([envs.step(a) for a in actions])
    for other in runs[1:]:
        for (obs, r, term, trunc, info), (o2, r2, t2, tr2, i2) in zip(runs[0], other):
            np.testing.assert_array_equal(obs, o2)
            np.testing.assert_array_equal(r, r2)
            np.testing.assert_array_equal(term, t2)
            np.testing.assert_array_equal(trunc, tr2)
            np.testing.assert_array_equal(info["eta_true"], i2["eta_true"])


@pytest.mark.skipif(not hasattr(os, "fork"), reason="needs fork()")
def test_a_process_forked_after_threaded_steps_steps_and_exits() -> None:
    """The kept threads are the parent's: a child forked from a process that
    stepped on them (as a study's worker processes are) steps on threads of
    its own and exits, static destructors and all, without hanging."""
    code = textwrap.dedent("""
        import os, sys
        import numpy as np
        from neurov.gym import TrackingVectorEnv
        from neurov import _core
        k = 2 * _core.MIN_LANES_PER_THREAD
        envs = TrackingVectorEnv(k, "paper_fig3", threads=2)
        envs.reset(seed=0)
        before = envs.step(np.zeros((k, 6), np.float32))[0]
        pid = os.fork()
        if pid == 0:
            child = TrackingVectorEnv(k, "paper_fig3", threads=2)
            child.reset(seed=0)
            same = np.array_equal(child.step(np.zeros((k, 6), np.float32))[0], before)
            sys.exit(0 if same else 3)
        _, status = os.waitpid(pid, 0)
        sys.exit(os.waitstatus_to_exitcode(status))
        """)
    done = subprocess.run([sys.executable, "-c", code], timeout=120, env={**os.environ,
                          "PYTHONPATH": os.pathsep.join(sys.path)})
    assert done.returncode == 0


def test_next_step_autoreset_ignores_the_action_and_restarts() -> None:
    envs = TrackingVectorEnv(2, _scenario())
    envs.reset(seed=3)
    zero = np.zeros((2, 6))
    for _ in range(7):
        obs, reward, terminated, truncated, info = envs.step(zero)
    assert truncated.all() and not terminated.any()
    # The next step resets: its action is ignored, reward 0, the episode's first row (a new noise draw).
    obs, reward, terminated, truncated, info = envs.step(np.full((2, 6), 0.9))
    np.testing.assert_array_equal(info["t"], [0.0, 0.0])
    assert not info["_plant_status"].any() and (reward == 0).all() and not (terminated | truncated).any()
    assert (info["action_clips"] == 0).all()
    envs.step(zero)
    assert envs.step(zero)[4]["t"][0] == pytest.approx(0.4)


def test_same_step_autoreset_returns_the_first_observation_and_the_final_one() -> None:
    scenario = _scenario("nerov_square_disturbed")  # with measurement noise
    nxt = TrackingVectorEnv(2, scenario)
    same = gymnasium.make_vec("neurov/Tracking-v0", num_envs=2, vectorization_mode="vector_entry_point",
                              scenario=scenario, autoreset_mode="SameStep")
    assert same.metadata["autoreset_mode"] == AutoresetMode.SAME_STEP
    nxt.reset(seed=9)
    same.reset(seed=9)
    a = np.full((2, 6), 0.1)
    for _ in range(6):
        o1, r1, *_ = nxt.step(a)
        o2, r2, _, _, info = same.step(a)
        np.testing.assert_array_equal(o1, o2)
        assert "final_obs" not in info
    o1, r1, te1, tr1, info1 = nxt.step(a)
    o2, r2, te2, tr2, info = same.step(a)
    np.testing.assert_array_equal(r1, r2)
    assert tr2.all() and (tr1 == tr2).all() and (te1 == te2).all()
    assert info["_final_obs"].all() and info["_final_info"].all()
    for i in range(2):
        np.testing.assert_array_equal(info["final_obs"][i], o1[i])
    for key in ("t", "eta", "eta_true", "action_clips"):
        np.testing.assert_array_equal(info["final_info"][key], info1[key])
        assert info["final_info"][f"_{key}"].all()
    np.testing.assert_array_equal(info["t"], [0.0, 0.0])
    # The reset NEXT_STEP makes one step later: the same first observation.
    o1, *_ = nxt.step(a)
    np.testing.assert_array_equal(o1, o2)


def test_seeds_fix_the_episodes_and_differ_between_envs() -> None:
    envs = TrackingVectorEnv(3, "nerov_square_disturbed")  # with measurement noise
    a, _ = envs.reset(seed=5)
    b, _ = envs.reset(seed=5)
    np.testing.assert_array_equal(a, b)
    assert not np.array_equal(a[0], a[1])  # env i is seeded with 5 + i
    c, _ = envs.reset(seed=[6, 7, 5])
    np.testing.assert_array_equal(c[2], a[0])
    np.testing.assert_array_equal(c[0], a[1])
    # Unseeded resets go on from each env's own generator.
    d, _ = envs.reset()
    assert not np.array_equal(d, c)


def _true_after_one_step(envs: TrackingVectorEnv) -> np.ndarray:
    return envs.step(np.zeros((envs.num_envs, 6)))[4]["eta_true"]


def test_randomize_draws_per_env_and_episode_and_repeats_from_the_seed() -> None:
    # Zero forces: the true motion depends on the plant alone (not on the measurement noise).
    plain = TrackingVectorEnv(2, _scenario("nerov_square_disturbed"))
    plain.reset(seed=[1, 2])
    base = _true_after_one_step(plain)
    np.testing.assert_array_equal(base[0], base[1])
    envs = TrackingVectorEnv(2, _scenario("nerov_square_disturbed"), randomize=RANDOMIZE)
    envs.reset(seed=[1, 2])
    first = _true_after_one_step(envs)
    assert not np.allclose(first[0], first[1], rtol=1e-9, atol=0)  # each env its own plant
    envs.reset()
    second = _true_after_one_step(envs)
    assert not np.allclose(first[0], second[0], rtol=1e-9, atol=0)  # each episode a new draw
    envs.reset(seed=[1, 2])
    np.testing.assert_array_equal(_true_after_one_step(envs), first)
    envs.reset(seed=[2, 2])
    np.testing.assert_array_equal(_true_after_one_step(envs)[0], first[1])


def test_bad_arguments_are_refused_naming_them() -> None:
    with pytest.raises(ValueError, match="num_envs"):
        TrackingVectorEnv(0)
    with pytest.raises(ValueError, match="autoreset_mode"):
        TrackingVectorEnv(2, autoreset_mode="Disabled")
    with pytest.raises(ValueError, match=r"randomize.*perturbations\[0\].*parameter"):
        TrackingVectorEnv(2, randomize=[{"parameter": "mas", "relative": 0.1}])
    with pytest.raises(ValueError, match="relative"):
        TrackingVectorEnv(2, randomize=[{"parameter": "mass", "relative": 1.5}])
    envs = TrackingVectorEnv(2)
    with pytest.raises(RuntimeError, match="reset"):
        envs.step(np.zeros((2, 6)))
    with pytest.raises(ValueError, match="env 1's seed"):
        envs.reset(seed=[0, -1])
    envs.reset(seed=0)
    with pytest.raises(ValueError, match=r"shape \(2, 6\)"):
        envs.step(np.zeros(6))
    bad = np.zeros((2, 6))
    bad[1, 2] = np.nan
    with pytest.raises(ValueError, match="row 1"):
        envs.step(bad)
    with pytest.raises(TypeError, match="real numbers"):
        envs.step(np.zeros((2, 6), dtype=bool))
    # Nothing was stepped.
    assert envs.step(np.zeros((2, 6)))[4]["t"][0] == pytest.approx(0.2)


def test_close_releases_the_batch() -> None:
    envs = TrackingVectorEnv(2)
    envs.reset(seed=0)
    envs.close()
    assert envs.closed
    envs.close()
    with pytest.raises(RuntimeError, match="closed"):
        envs.step(np.zeros((2, 6)))
    with pytest.raises(RuntimeError, match="closed"):
        envs.reset()


class _OneLane(gymnasium.Env):
    """Lane 0 of a one-env vector env as a gymnasium.Env, for check_env."""

    def __init__(self, randomize: Any) -> None:
        self.vec = TrackingVectorEnv(1, _scenario(), randomize=randomize, autoreset_mode="SameStep")
        self.observation_space = self.vec.single_observation_space
        self.action_space = self.vec.single_action_space

    def reset(self, *, seed: int | None = None, options: Any = None) -> tuple[Any, dict[str, Any]]:
        super().reset(seed=seed)
        obs, info = self.vec.reset(seed=seed)
        return obs[0], {k: v[0] for k, v in info.items()}

    def step(self, action: Any) -> tuple[Any, float, bool, bool, dict[str, Any]]:
        obs, r, term, trunc, info = self.vec.step(np.asarray(action)[None])
        if term[0] or trunc[0]:
            obs = info["final_obs"]
        return obs[0], float(r[0]), bool(term[0]), bool(trunc[0]), {"t": float(info["t"][0])}


@pytest.mark.parametrize("randomize", [None, RANDOMIZE])
def test_check_env_passes_on_one_lane(randomize: Any) -> None:
    check_env(_OneLane(randomize), skip_render_check=True)
    check_env(TrackingEnv(_scenario(), randomize=randomize), skip_render_check=True)
