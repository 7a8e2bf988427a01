"""K runs stepped together with the interface of the compiled
``neurov._core.BatchSimulator``, each run a single ``_core.Simulator``: the
reference the vector env and the batched-policy loop are tested against
with the compiled batch (docs/gymnasium.md)."""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import numpy as np
from numpy.typing import NDArray

from neurov import _core

__all__ = ["PythonLanes"]

_FIELDS = ("eta", "nu", "eta_d", "eta_d_dot", "eta_d_ddot")


class PythonLanes:
    """``BatchSimulator(vehicles, configs, logged_parameters)`` run lane by
    lane in Python: the same properties and methods, the same shapes."""

    def __init__(self, vehicles: Sequence[_core.Vehicle], configs: Sequence[_core.SimulationConfig],
                 logged_parameters: int = 0) -> None:
        if len(vehicles) != len(configs) or not vehicles:
            raise ValueError(f"arguments 'vehicles' and 'configs' must be lists of the same length >= 1, "
                             f"got {len(vehicles)} and {len(configs)}")
        self._logged = logged_parameters
        self._lanes = [_core.Simulator(v, c, logged_parameters) for v, c in zip(vehicles, configs)]

    @property
    def size(self) -> int:
        return len(self._lanes)

    @property
    def observation(self) -> dict[str, NDArray[Any]]:
        obs = [lane.observation for lane in self._lanes]
        out: dict[str, NDArray[Any]] = {"t": np.array([o.t for o in obs])}
        for name in _FIELDS:
            out[name] = np.array([getattr(o, name) for o in obs])
        out["faults"] = np.array([lane.faults for lane in self._lanes], dtype=np.uint8)
        return out

    @property
    def state(self) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        states = [lane.state for lane in self._lanes]
        return np.array([s[0] for s in states]), np.array([s[1] for s in states])

    def _mask(self, mask: Any) -> NDArray[np.bool_]:
        if mask is None:
            return np.ones(self.size, dtype=bool)
        m = np.asarray(mask)
        if m.dtype != np.bool_ or m.shape != (self.size,):
            raise ValueError(f"argument 'mask' must be a bool array of shape ({self.size},), "
                             f"got {m.dtype} {m.shape}")
        return m

    def step(self, tau: Any, mask: Any = None) -> NDArray[np.uint8]:
        """Steps every lane in `mask` that is not done with its row of tau (K, 6)."""
        forces = np.asarray(tau, dtype=np.float64)
        if forces.shape != (self.size, 6):
            raise ValueError(f"argument 'tau' must have shape ({self.size}, 6), got {forces.shape}")
        statuses = np.full(self.size, _core.LANE_NOT_STEPPED, dtype=np.uint8)
        for i in np.flatnonzero(self._mask(mask)):
            lane = self._lanes[i]
            if not lane.done:
                statuses[i] = int(lane.step(forces[i]))
        return statuses

    @property
    def done(self) -> NDArray[np.bool_]:
        return np.array([lane.done for lane in self._lanes])

    @property
    def diverged(self) -> NDArray[np.bool_]:
        return np.array([lane.diverged for lane in self._lanes])

    @property
    def steps(self) -> NDArray[np.int64]:
        return np.array([lane.steps for lane in self._lanes], dtype=np.int64)

    @property
    def planned_steps(self) -> NDArray[np.int64]:
        return np.array([lane.planned_steps for lane in self._lanes], dtype=np.int64)

    def reset(self, seeds: Any, mask: Any = None) -> None:
        """Back to t = 0, lane i with noise from seeds[i], the lanes in `mask`."""
        s = np.asarray(seeds)
        if s.shape != (self.size,) or s.dtype.kind not in "iu":
            raise ValueError(f"argument 'seeds' must be an integer array of shape ({self.size},), "
                             f"got {s.dtype} {s.shape}")
        for i in np.flatnonzero(self._mask(mask)):
            self._lanes[i].reset(int(s[i]))

    def replace(self, i: int, vehicle: _core.Vehicle, config: _core.SimulationConfig) -> None:
        """Lane i becomes a run of `vehicle` under `config`, at t = 0."""
        self._lanes[i] = _core.Simulator(vehicle, config, self._logged)

    def result(self, i: int) -> dict[str, Any]:
        """Lane i's rows, as ``_core.Simulator.result`` gives them."""
        return self._lanes[i].result()
