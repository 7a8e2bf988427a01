"""The NN controller's weights saved to and loaded from a .npz file."""

from __future__ import annotations

import io
import os
import sys
import tracemalloc
import zipfile
from pathlib import Path
from typing import Any

import numpy as np
import pytest

import neurov
from neurov import files
from neurov.laws.weights import WeightsFileError, load_network, load_weights, read_weights, save_weights

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


# ------------------------------------------- files that are not weights files
# (issue 23: read as neurov.files reads, every size bounded before allocation)

posix_only = pytest.mark.skipif(sys.platform == "win32", reason="device files and FIFOs are POSIX")


@posix_only
def test_a_fifo_is_refused_without_blocking(tmp_path: Path) -> None:
    fifo = tmp_path / "w.npz"
    os.mkfifo(fifo)  # no writer: np.load blocked for ever on it
    with pytest.raises(WeightsFileError, match="is a FIFO") as err:
        load_weights(_controller(), fifo)
    assert str(fifo) in str(err.value)


@posix_only
def test_dev_zero_is_not_a_regular_file() -> None:
    with pytest.raises(WeightsFileError, match="/dev/zero: is a character device, not a regular file"):
        read_weights("/dev/zero")


def test_a_file_over_the_limit_is_refused_unread(tmp_path: Path) -> None:
    big = tmp_path / "big.npz"
    with big.open("wb") as f:
        f.truncate(files.MAX_WEIGHTS_FILE_BYTES + 1)  # sparse
    with pytest.raises(WeightsFileError, match=f"larger than {files.MAX_WEIGHTS_FILE_BYTES} bytes"):
        read_weights(big)


def test_a_single_npy_array_gets_its_own_message(tmp_path: Path) -> None:
    path = tmp_path / "w.npy"
    np.save(path, _controller().weights)
    with pytest.raises(WeightsFileError, match=r"a single \.npy array, not a \.npz archive") as err:
        read_weights(path)
    assert str(path) in str(err.value) and "save_weights" in str(err.value)


def _saved(tmp_path: Path, n: int = 6) -> tuple[Path, bytes]:
    path = tmp_path / "good.npz"
    _controller(n).save(path)
    return path, path.read_bytes()


def test_every_truncation_is_a_named_error(tmp_path: Path) -> None:
    good, data = _saved(tmp_path, n=1)
    for size in range(len(data) - 1, -1, -1):  # the file cut one byte shorter each time
        os.truncate(good, size)
        with pytest.raises(WeightsFileError, match=f"weights file {good}: "):
            read_weights(good)


def test_a_flipped_bit_is_an_error_or_changes_nothing(tmp_path: Path) -> None:
    """Every third byte of a small file flipped in turn (one bit each, the
    bit cycling): the file is refused naming it and what is wrong (CRC, zip
    structure, header), or, where the byte is one the reader does not use (a
    time stamp), it reads the same numbers bit for bit."""
    good, data = _saved(tmp_path, n=1)
    want = read_weights(good)
    refused = 0
    positions = range(0, len(data), 3)
    with open(good, "r+b", buffering=0) as f:  # flipped in place: no file made per case
        for i in positions:
            f.seek(i)
            f.write(bytes([data[i] ^ (1 << (i % 8))]))
            try:
                got = read_weights(good)
            except WeightsFileError as e:
                assert str(good) in str(e)
                refused += 1
            else:
                for name in ("weights", "centres", "widths", "input_offset", "input_scale"):
                    assert np.array_equal(getattr(got, name), getattr(want, name)), (i, name)
            f.seek(i)
            f.write(data[i:i + 1])
    assert refused > len(positions) // 2


def _member(archive: zipfile.ZipFile, name: str, shape: tuple[int, ...], dtype: str, data: bytes,
            compress: bool = False) -> None:
    """An .npy member whose header declares `shape` whatever `data` holds."""
    head = io.BytesIO()
    np.lib.format.write_array_header_1_0(head, {"descr": dtype, "fortran_order": False, "shape": shape})
    archive.writestr(f"{name}.npy", head.getvalue() + data,
                     zipfile.ZIP_DEFLATED if compress else zipfile.ZIP_STORED)


def _archive(path: Path, members: dict[str, tuple[tuple[int, ...], str, bytes]], good: Path,
             compress: bool = False) -> None:
    with np.load(good) as saved, zipfile.ZipFile(path, "w") as out:
        for name in ("format", "version", "weights", "centres", "widths", "input_offset", "input_scale"):
            if name in members:
                _member(out, name, *members[name], compress=compress)
            else:
                a = saved[name]
                _member(out, name, a.shape, np.lib.format.dtype_to_descr(a.dtype), a.tobytes())


@pytest.mark.parametrize(
    ("members", "message"),
    [
        pytest.param({"centres": ((10**8, 24), "<f8", b"")},
                     r"'centres' declares 100000000 centres, more than the 65536", id="18 GiB of centres"),
        pytest.param({"weights": ((6, 10**9), "<f8", b"")},
                     r"'weights' must have shape \(6, 6\), got \(6, 1000000000\)", id="48 GB of weights"),
        pytest.param({"format": ((), "<U100000000", b"")}, "'format' must be 'neurov-nn-weights'",
                     id="a 400 MB string"),
        pytest.param({"widths": ((6,), "|O", b"")}, "holds Python objects", id="objects"),
        pytest.param({"widths": ((-6,), "<f8", b"")}, r"'widths' declares the shape \(-6,\)",
                     id="negative shape"),
        pytest.param({"widths": ((6,), "<f8", b"\0" * 8)}, "'widths' is truncated: 8 of the 48 bytes",
                     id="data shorter than declared"),
    ],
)
def test_declared_sizes_are_checked_before_anything_is_allocated(
        tmp_path: Path, members: dict[str, Any], message: str) -> None:
    good, _ = _saved(tmp_path)
    path = tmp_path / "declared.npz"
    _archive(path, members, good)
    tracemalloc.start()
    try:
        with pytest.raises(WeightsFileError, match=message) as err:
            read_weights(path)
        peak = tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()
    assert str(path) in str(err.value)
    assert peak < 2 * 1024 * 1024  # numpy reports its buffers to tracemalloc


def test_a_member_that_inflates_past_the_limit_is_refused(tmp_path: Path) -> None:
    """A small file of compressed zeros whose member declares more bytes than
    a weights file may hold (np.load inflated a 375 kB file to 384 MB)."""
    good, _ = _saved(tmp_path)
    path = tmp_path / "bomb.npz"
    n = files.MAX_WEIGHTS_FILE_BYTES // 8 + 1
    _archive(path, {"widths": ((n,), "<f8", bytes(8 * n))}, good, compress=True)
    assert path.stat().st_size < 100_000
    with pytest.raises(WeightsFileError, match=rf"array 'widths' declares \d+ bytes, more than "
                                               f"the {files.MAX_WEIGHTS_FILE_BYTES}"):
        read_weights(path)


def test_a_network_of_the_most_centres_fits_the_file_limit(tmp_path: Path) -> None:
    """save_weights of a MAX_CENTRES network is read back: the two limits agree."""
    n = neurov.MAX_CENTRES
    net = neurov.RbfNetwork(np.zeros((n, 24)), 1.0)
    path = tmp_path / "largest.npz"
    save_weights(net, path)
    assert path.stat().st_size <= files.MAX_WEIGHTS_FILE_BYTES
    assert read_weights(path).n_centres == n
