"""reset(options=...) of the tracking environments: the vector env's one
option is gymnasium's ``reset_mask`` (a partial reset, in either autoreset
mode); anything else is refused. Before, every option was ignored and a
reset_mask reset every env."""

from __future__ import annotations

from typing import Any

import numpy as np
import pytest

gymnasium = pytest.importorskip("gymnasium")
from neurov.gym import TrackingEnv, TrackingVectorEnv, resolve_scenario  # noqa: E402

SHORT = resolve_scenario("paper_fig3").replace(duration=1.2)  # 6 steps an episode


@pytest.mark.parametrize(("options", "error", "match"), [
    ({"no_such_option": 1}, ValueError, r"unknown key\(s\) 'no_such_option'; the one option is 'reset_mask'"),
    ("reset_mask", TypeError, r"'options' must be None or a dict .*got str"),
    ([True, False], TypeError, r"'options' must be None or a dict .*got list"),
    ({"reset_mask": [True, False, True]}, TypeError, r"'reset_mask' must be a numpy bool array of shape \(3,\), got list"),
    ({"reset_mask": np.ones(2, dtype=bool)}, TypeError, r"shape \(3,\), got an array of bool \(2,\)"),
    ({"reset_mask": np.ones(3)}, TypeError, r"got an array of float64 \(3,\)"),
    ({"reset_mask": np.zeros(3, dtype=bool)}, ValueError, r"at least one True"),
])
def test_bad_options_are_refused(options: Any, error: type, match: str) -> None:
    envs = TrackingVectorEnv(3, SHORT)
    envs.reset(seed=1)
    with pytest.raises(error, match=match):
        envs.reset(options=options)


def test_the_single_env_takes_no_options() -> None:
    env = TrackingEnv(SHORT)
    env.reset(options={})
    with pytest.raises(ValueError, match=r"'options': TrackingEnv.reset takes no options"):
        env.reset(options={"reset_mask": np.ones(1, dtype=bool)})


@pytest.mark.parametrize("mode", ["NextStep", "SameStep"])
def test_reset_mask_resets_only_its_envs(mode: str) -> None:
    envs = TrackingVectorEnv(3, SHORT, autoreset_mode=mode)
    first, _ = envs.reset(seed=10)
    action = np.full((3, 6), 5.0, dtype=np.float32)
    for _ in range(2):
        moved, *_ = envs.step(action)
    mask = np.array([False, True, False])
    obs, info = envs.reset(seed=[None, 11, None], options={"reset_mask": mask})
    np.testing.assert_array_equal(obs[[0, 2]], moved[[0, 2]])  # untouched: as they stood
    np.testing.assert_array_equal(obs[1], first[1])  # env 1 again from its first seed: its first observation
    assert info["t"][1] == 0.0 and (info["t"][[0, 2]] > 0).all()
    np.testing.assert_array_equal(info["_t"], mask)
    again, *_ = envs.step(action)
    assert again[1].tolist() != again[0].tolist()


def test_reset_mask_clears_a_pending_next_step_autoreset() -> None:
    envs = TrackingVectorEnv(2, SHORT)
    envs.reset(seed=0)
    zero = np.zeros((2, 6), dtype=np.float32)
    truncated = np.zeros(2, dtype=bool)
    while not truncated.any():
        _, _, _, truncated, _ = envs.step(zero)
    _, info = envs.reset(seed=[5, None], options={"reset_mask": np.array([True, False])})
    assert info["t"][0] == 0.0 and info["t"][1] > 1.0
    _, reward, _, _, info = envs.step(zero)
    assert info["_plant_status"].tolist() == [True, False]  # env 0 stepped (reset by the mask), env 1 autoreset
    assert info["t"].tolist() == [0.2, 0.0] and reward[1] == 0.0


def test_a_partial_reset_before_the_first_reset_is_refused() -> None:
    envs = TrackingVectorEnv(2, SHORT)
    with pytest.raises(RuntimeError, match="before the first reset"):
        envs.reset(options={"reset_mask": np.array([True, False])})
