"""The block bootstrap's intervals with few blocks: the percentiles
stretched by sqrt(G / (G - 1)) t_{G-1} / z cover a mean of G block
contributions at the nominal rate, the raw percentiles short of it."""

from __future__ import annotations

import numpy as np
import pytest

from neurov.identification.blocks import Blocks, small_sample_scale


def _coverage(n_blocks: int, trials: int, stretch: bool, replicates: int = 1000) -> float:
    rng = np.random.default_rng(11)
    hits = 0
    for k in range(trials):
        x = rng.normal(size=n_blocks)  # each block's contribution; the true mean is 0
        b = Blocks(np.ones((n_blocks, 1, 1)), x[:, None])
        est = b.solve()[0]
        q = np.percentile(b.bootstrap(replicates, k)[:, 0], [2.5, 97.5])
        if stretch:
            q = est + small_sample_scale(n_blocks) * (q - est)
        hits += q[0] <= 0.0 <= q[1]
    return hits / trials


def test_twelve_blocks_cover_at_the_nominal_rate_only_stretched() -> None:
    # (identify's 1000 draws; raw, P(|t_11| < 1.96 sqrt(11/12)) = 0.91 expected;
    # measured on 1000 trials from 200 draws: raw 0.89, stretched 0.93; from 1000, stretched 0.94;
    # on these 300 from 1000 draws: raw 0.92, stretched 0.95)
    raw, stretched = _coverage(12, 300, False), _coverage(12, 300, True)
    assert raw < 0.935 <= stretched <= 0.97


def test_the_stretch_goes_to_one_with_many_blocks_and_bad_input_is_named() -> None:
    assert small_sample_scale(12) > small_sample_scale(24) > small_sample_scale(1000) > 1.0
    assert small_sample_scale(1000) < 1.002
    with pytest.raises(ValueError, match="n_blocks: expected at least 2 blocks, got 1"):
        small_sample_scale(1)
    with pytest.raises(ValueError, match="level: expected a probability in \\(0, 1\\), got 1.5"):
        small_sample_scale(12, 1.5)
