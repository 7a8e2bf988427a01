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


def _get(data: Any, path: Any, name: str) -> np.ndarray:
    """One array of the archive; a missing one or one of Python objects
    (refused, never unpickled) is a WeightsFileError naming it."""
    if name not in data.files:
        raise WeightsFileError(f"weights file {path}: array '{name}' is missing")
    try:
        return np.asarray(data[name])
    except ValueError as e:
        raise WeightsFileError(f"weights file {path}: array '{name}' is not plain numbers ({e})") from None


def _array(data: Any, path: Any, name: str, shape: tuple[int, ...]) -> np.ndarray:
    a = _get(data, path, name)
    if a.dtype.kind not in "fi":
        raise WeightsFileError(f"weights file {path}: '{name}' must be numbers, got dtype {a.dtype}")
    if a.shape != shape:
        want = "(" + ", ".join(str(n) for n in shape) + ("," if len(shape) == 1 else "") + ")"
        raise WeightsFileError(f"weights file {path}: '{name}' must have shape {want}, got {a.shape}")
    a = a.astype(np.float64)
    if not np.all(np.isfinite(a)):
        raise WeightsFileError(f"weights file {path}: '{name}' holds NaN or Inf")
    return a


def read_weights(path: str | os.PathLike[str]) -> NetworkWeights:
    """Reads and checks a weights file; WeightsFileError names the file and
    the array that is missing, of the wrong shape or not finite."""
    try:
        data = np.load(path, allow_pickle=False)
    except FileNotFoundError:
        raise
    except (OSError, ValueError) as e:
        raise WeightsFileError(f"weights file {path}: not a .npz archive of plain arrays ({e})") from None
    with data:
        if not hasattr(data, "files"):
            raise WeightsFileError(f"weights file {path}: not a .npz archive (a single array)")
        fmt = _get(data, path, "format")
        if fmt.shape != () or fmt.dtype.kind != "U" or str(fmt) != FORMAT:
            raise WeightsFileError(f"weights file {path}: 'format' must be '{FORMAT}'")
        version = _get(data, path, "version")
        if version.shape != () or version.dtype.kind not in "iu" or int(version) != VERSION:
            raise WeightsFileError(f"weights file {path}: 'version' must be {VERSION}")
        centres = _get(data, path, "centres")
        if centres.ndim != 2:
            raise WeightsFileError(f"weights file {path}: 'centres' must have shape (N, {N_INPUTS})")
        n = int(centres.shape[0])
        return NetworkWeights(
            weights=_array(data, path, "weights", (6, n)),
            centres=_array(data, path, "centres", (n, N_INPUTS)),
            widths=_array(data, path, "widths", (n,)),
            input_offset=_array(data, path, "input_offset", (N_INPUTS,)),
            input_scale=_array(data, path, "input_scale", (N_INPUTS,)),
        )


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
        .npz file (format: :mod:`neurov.weights`)."""
        save_weights(self, path)

    def load(self: Any, path: str | os.PathLike[str]) -> None:
        """Sets the current weights W from a file written by save();
        :class:`WeightsFileError` names a file of the wrong shape or network."""
        load_weights(self, path)

    _core.NNAdaptiveController.save = save
    _core.NNAdaptiveController.load = load


_attach_methods()
