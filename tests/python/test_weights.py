"""The NN controller's weights saved to and loaded from a .npz file."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

import neurov
from neurov.weights import WeightsFileError, load_network, load_weights, read_weights, save_weights

LAM = np.full(6, 0.8)
KD = np.full(6, 100.0)


def _controller(n: int = 6, seed: int = 3) -> neurov.NNAdaptiveController:
    rng = np.random.default_rng(seed)
    net = neurov.RbfNetwork(rng.normal(size=(n, 24)), rng.uniform(2, 4, n), rng.normal(size=24),
                            rng.uniform(0.5, 2.0, 24))
    return neurov.NNAdaptiveController(net, LAM, KD, 0.5, 0.1)


def _train(ctl: neurov.NNAdaptiveController, steps: int = 20) -> None:
    rng = np.random.default_rng(9)
    for _ in range(steps):
        eta = rng.normal(scale=0.4, size=6)
        eta[4] = 0.2
        ctl.step(eta, rng.normal(scale=0.3, size=6), rng.normal(size=6), np.zeros(6), np.zeros(6))


def test_saved_weights_load_into_a_fresh_controller(tmp_path: Path) -> None:
    trained = _controller()
    _train(trained)
    path = tmp_path / "trained.npz"
    trained.save(path)
    fresh = _controller()
    assert not np.array_equal(fresh.weights, trained.weights)
    fresh.load(path)
    assert fresh.weights.tobytes() == trained.weights.tobytes()


def test_the_file_holds_the_documented_plain_arrays(tmp_path: Path) -> None:
    ctl = _controller()
    _train(ctl)
    path = tmp_path / "w.npz"
    save_weights(ctl, path)
    with np.load(path, allow_pickle=False) as data:
        assert sorted(data.files) == sorted(
            ["format", "version", "weights", "centres", "widths", "input_offset", "input_scale"])
        assert str(data["format"]) == "neurov-nn-weights" and int(data["version"]) == 1
        assert data["weights"].shape == (6, 6) and data["centres"].shape == (6, 24)
        np.testing.assert_array_equal(data["weights"], ctl.weights)
        np.testing.assert_array_equal(data["centres"], ctl.centres)
        np.testing.assert_array_equal(data["input_scale"], ctl.input_scale)


def test_load_network_starts_a_new_controller_from_the_saved_weights(tmp_path: Path) -> None:
    ctl = _controller()
    _train(ctl)
    path = tmp_path / "w.npz"
    ctl.save(path)
    net = load_network(path)
    again = neurov.NNAdaptiveController(net, LAM, KD, 0.5, 0.1)
    assert again.weights.tobytes() == ctl.weights.tobytes()
    again.reset()  # W(0) is the saved W
    assert again.weights.tobytes() == ctl.weights.tobytes()


def test_a_network_of_another_size_is_a_named_error(tmp_path: Path) -> None:
    path = tmp_path / "w.npz"
    _controller(n=6).save(path)
    other = _controller(n=8)
    before = other.weights
    with pytest.raises(WeightsFileError, match=r"network size 6 centres, the NNAdaptiveController has 8"):
        other.load(path)
    assert other.weights.tobytes() == before.tobytes()


def test_another_network_of_the_same_size_is_a_named_error(tmp_path: Path) -> None:
    path = tmp_path / "w.npz"
    _controller(seed=3).save(path)
    with pytest.raises(WeightsFileError, match="'centres' differs"):
        _controller(seed=4).load(path)


def _write(path: Path, **arrays: np.ndarray) -> None:
    with open(path, "wb") as f:
        np.savez(f, **arrays)


def _good(tmp_path: Path) -> dict[str, np.ndarray]:
    path = tmp_path / "good.npz"
    _controller().save(path)
    with np.load(path) as data:
        return {k: data[k] for k in data.files}


@pytest.mark.parametrize(
    ("field", "value", "message"),
    [
        ("weights", np.zeros((5, 6)), r"'weights' must have shape \(6, 6\), got \(5, 6\)"),
        ("weights", np.zeros(36), r"'weights' must have shape \(6, 6\)"),
        ("widths", np.ones(7), r"'widths' must have shape \(6,\), got \(7,\)"),
        ("centres", np.zeros((6, 12)), r"'centres' must have shape \(6, 24\)"),
        ("centres", np.zeros(24), r"'centres' must have shape \(N, 24\)"),
        ("input_scale", np.ones(23), r"'input_scale' must have shape \(24,\)"),
        ("weights", np.full((6, 6), np.nan), "'weights' holds NaN or Inf"),
        ("format", np.array("something else"), "'format' must be 'neurov-nn-weights'"),
        ("version", np.array(2), "'version' must be 1"),
    ],
)
def test_a_file_of_the_wrong_shape_is_a_named_error(tmp_path: Path, field: str, value: np.ndarray,
                                                    message: str) -> None:
    arrays = _good(tmp_path)
    arrays[field] = value
    path = tmp_path / "bad.npz"
    _write(path, **arrays)
    with pytest.raises(WeightsFileError, match=message) as info:
        read_weights(path)
    assert str(path) in str(info.value)


def test_a_missing_array_is_named(tmp_path: Path) -> None:
    arrays = _good(tmp_path)
    del arrays["widths"]
    path = tmp_path / "bad.npz"
    _write(path, **arrays)
    with pytest.raises(WeightsFileError, match="array 'widths' is missing"):
        load_weights(_controller(), path)


def test_pickled_objects_are_refused_not_run(tmp_path: Path) -> None:
    arrays = _good(tmp_path)
    arrays["weights"] = np.array([{"a": 1}], dtype=object)
    path = tmp_path / "bad.npz"
    _write(path, **arrays)
    with pytest.raises(WeightsFileError, match="weights file"):
        read_weights(path)


def test_a_file_that_is_not_npz_is_named(tmp_path: Path) -> None:
    path = tmp_path / "w.npz"
    path.write_text("not an archive", encoding="utf-8")
    with pytest.raises(WeightsFileError, match="not a .npz archive"):
        read_weights(path)
