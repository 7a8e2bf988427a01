"""The NN controller's learnt weights in a file, to keep a trained network.

A weights file is a NumPy ``.npz`` archive (read with ``allow_pickle=False``,
so it holds plain arrays and nothing that runs code) with these arrays:

==================  ==========  ==================================================
name                shape       meaning
==================  ==========  ==================================================
``format``          ()          the string ``"neurov-nn-weights"``
``version``         ()          ``1``
``weights``         (6, N)      W: row i is output i (tau's DOF), column j centre j
``centres``         (N, 24)     the centres xi_j, one per row
``widths``          (N,)        sigma_j
``input_offset``    (24,)       input normalisation x_hat = (x - offset) * scale
``input_scale``     (24,)
==================  ==========  ==================================================

All float arrays are float64. The centres, widths and input normalisation
are what make the weights mean something: :func:`load_weights` refuses a
file whose network differs from the controller's, naming what differs.
A file is read as :mod:`neurov.files` reads (a regular file, at most
``MAX_WEIGHTS_FILE_BYTES``, 24 MiB), and each array's declared shape is
checked before the array is read (N at most ``neurov.MAX_CENTRES``), so a
file can ask for no more memory than a network of the largest size.
On a board, ``weights`` flattened in C (row-major) order, as float32, is the
buffer ``neurov_nn_set_initial_weights`` takes (docs/firmware.md).
"""

from __future__ import annotations

import os
from dataclasses import dataclass
from typing import Any

import numpy as np

from neurov import _core
from neurov.errors import WeightsFileError
from neurov.files import MAX_WEIGHTS_FILE_BYTES
from neurov.npz_file import NpzFile

FORMAT = "neurov-nn-weights"
VERSION = 1
N_INPUTS = 24
_ARRAYS = ("weights", "centres", "widths", "input_offset", "input_scale")


@dataclass(frozen=True)
class NetworkWeights:
    """What a weights file holds (see the module's table)."""

    weights: np.ndarray
    centres: np.ndarray
    widths: np.ndarray
    input_offset: np.ndarray
    input_scale: np.ndarray

    @property
    def n_centres(self) -> int:
        return int(self.centres.shape[0])


def _network_of(obj: Any) -> NetworkWeights:
    """The weights and network of an NNAdaptiveController or an RbfNetwork."""
    return NetworkWeights(
        *(np.array(getattr(obj, name), dtype=np.float64) for name in _ARRAYS)
    )


def save_weights(obj: Any, path: str | os.PathLike[str]) -> None:
    """Writes the current weights W of `obj` (an NNAdaptiveController or an
    RbfNetwork) and its network to `path` (.npz, written at exactly `path`)."""
    net = _network_of(obj)
    if net.centres.ndim != 2 or net.centres.shape[1] != N_INPUTS:
        raise WeightsFileError(
            f"save_weights: the network must have {N_INPUTS} inputs (the NN controller's), "
            f"got centres of shape {net.centres.shape}"
        )
    with open(path, "wb") as f:
        np.savez(f, format=np.array(FORMAT), version=np.array(VERSION),
                 **{name: getattr(net, name) for name in _ARRAYS})


def _shape_text(shape: tuple[int | str, ...]) -> str:
    return "(" + ", ".join(str(n) for n in shape) + ("," if len(shape) == 1 else "") + ")"


def _numbers(where: str, name: str, shape: tuple[int, ...]) -> Any:
    """The check of a float array's header: exactly `shape`, real numbers
    (so at most 16 bytes each: what is allocated is bounded by the shape)."""

    def check(got: tuple[int, ...], dtype: np.dtype) -> None:
        if dtype.kind not in "fi":
            raise WeightsFileError(f"{where}: '{name}' must be numbers, got dtype {dtype}")
        if got != shape:
            raise WeightsFileError(f"{where}: '{name}' must have shape {_shape_text(shape)}, "
                                   f"got {_shape_text(got)}")

    return check


def _scalar(where: str, name: str, kinds: str, itemsize: int, wanted: str) -> Any:
    def check(shape: tuple[int, ...], dtype: np.dtype) -> None:
        if shape != () or dtype.kind not in kinds or dtype.itemsize > itemsize:
            raise WeightsFileError(f"{where}: '{name}' must be {wanted}")

    return check


def _finite(where: str, name: str, a: np.ndarray) -> np.ndarray:
    a = a.astype(np.float64)
    if not np.all(np.isfinite(a)):
        raise WeightsFileError(f"{where}: '{name}' holds NaN or Inf")
    return a


def read_weights(path: str | os.PathLike[str]) -> NetworkWeights:
    """Reads and checks a weights file; WeightsFileError names the file and
    what is wrong: not a regular file, over ``neurov.files.MAX_WEIGHTS_FILE_BYTES``,
    not a .npz archive, truncated or damaged, an array missing, of the wrong
    shape, of more than ``neurov.MAX_CENTRES`` centres or not finite. Every
    shape is checked before its array is allocated."""
    where = f"weights file {path}"
    with NpzFile(path, WeightsFileError, MAX_WEIGHTS_FILE_BYTES, where,
                 "; write one with save_weights or NNAdaptiveController.save") as data:
        fmt = data.array("format", _scalar(where, "format", "U", 4 * 64, f"'{FORMAT}'"))
        if str(fmt) != FORMAT:
            raise WeightsFileError(f"{where}: 'format' must be '{FORMAT}'")
        version = data.array("version", _scalar(where, "version", "iu", 8, str(VERSION)))
        if int(version) != VERSION:
            raise WeightsFileError(f"{where}: 'version' must be {VERSION}")
        shape, _ = data.header("centres")
        if len(shape) != 2:
            raise WeightsFileError(f"{where}: 'centres' must have shape (N, {N_INPUTS})")
        n = shape[0]
        if n > _core.MAX_CENTRES:
            raise WeightsFileError(f"{where}: 'centres' declares {n} centres, more than the "
                                   f"{_core.MAX_CENTRES} a network takes (neurov.MAX_CENTRES)")
        shapes = {"weights": (6, n), "centres": (n, N_INPUTS), "widths": (n,),
                  "input_offset": (N_INPUTS,), "input_scale": (N_INPUTS,)}
        return NetworkWeights(**{
            name: _finite(where, name, data.array(name, _numbers(where, name, shapes[name])))
            for name in _ARRAYS
        })


def load_network(path: str | os.PathLike[str]) -> Any:
    """An RbfNetwork rebuilt from a weights file, its weights W: pass it to
    NNAdaptiveController to start a new controller from what was learnt."""


    saved = read_weights(path)
    net = _core.RbfNetwork(saved.centres, saved.widths, saved.input_offset, saved.input_scale)
    net.weights = saved.weights
    return net


def load_weights(obj: Any, path: str | os.PathLike[str]) -> None:
    """Sets the current weights of `obj` (an NNAdaptiveController or an
    RbfNetwork) from a weights file whose network is the same: the same
    number of centres, and centres, widths and input normalisation equal to
    the bit; WeightsFileError names what differs and `obj` is unchanged."""
    saved = read_weights(path)
    mine = _network_of(obj)
    if saved.n_centres != mine.n_centres:
        raise WeightsFileError(
            f"weights file {path}: network size {saved.n_centres} centres, the "
            f"{type(obj).__name__} has {mine.n_centres}"
        )
    for name in ("centres", "widths", "input_offset", "input_scale"):
        if not np.array_equal(getattr(saved, name), getattr(mine, name)):
            raise WeightsFileError(
                f"weights file {path}: '{name}' differs from the {type(obj).__name__}'s "
                "(the weights belong to another network)"
            )
    obj.weights = saved.weights


def _attach_methods() -> None:
    """``NNAdaptiveController.save`` and ``.load`` write and read files, which
    is this package's work: attached here so that the compiled core never
    imports the Python package."""

    def save(self: Any, path: str | os.PathLike[str]) -> None:
        """Writes the current weights W and the network they belong to to a
        .npz file (format: :mod:`neurov.laws.weights`)."""
        save_weights(self, path)

    def load(self: Any, path: str | os.PathLike[str]) -> None:
        """Sets the current weights W from a file written by save();
        :class:`WeightsFileError` names a file of the wrong shape or network."""
        load_weights(self, path)

    _core.NNAdaptiveController.save = save
    _core.NNAdaptiveController.load = load


_attach_methods()
