"""What the actuators can give each DOF alone: the scale of the
environment's normalised actions."""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray
from scipy.optimize import linprog

__all__ = ["single_dof_limits"]

Array = NDArray[np.float64]
DOF_NAMES = ("X (surge force)", "Y (sway force)", "Z (heave force)", "K (roll moment)",
             "M (pitch moment)", "N (yaw moment)")


def single_dof_limits(matrix: Array, min_thrust: Array, max_thrust: Array) -> tuple[Array, Array]:
    """For each DOF i, the largest tau_i > 0 and the largest -tau_i > 0 that
    thrust u with ``min_thrust <= u <= max_thrust`` produces through
    ``tau = matrix @ u`` while the other five components of tau are zero: two
    linear programs per DOF. Returns (positive, negative), both (6,) and > 0;
    ValueError naming a DOF the thrusters cannot push both ways on its own."""
    matrix = np.asarray(matrix, dtype=np.float64)
    lo = np.asarray(min_thrust, dtype=np.float64)
    hi = np.asarray(max_thrust, dtype=np.float64)
    bounds = list(zip(lo.tolist(), hi.tolist()))
    out = np.zeros((2, 6))
    for i in range(6):
        others = np.delete(matrix, i, axis=0)
        for k, sign in enumerate((1.0, -1.0)):
            res = linprog(-sign * matrix[i], A_eq=others, b_eq=np.zeros(5), bounds=bounds, method="highs")
            if res.status != 0:
                raise ValueError(f"thrusters: the largest {DOF_NAMES[i]} could not be found ({res.message})")
            out[k, i] = -res.fun
    # The optimum is a vertex; the solver's tolerance makes "none" about 1e-9 of a thruster.
    weak = out <= 1e-9 * float(np.max(np.abs(np.concatenate([lo, hi]))))
    if weak.any():
        k, i = np.argwhere(weak)[0]
        raise ValueError(f"thrusters: the layout gives no {'negative' if k else 'positive'} {DOF_NAMES[i]} "
                         "with the other DOFs zero, so that DOF cannot be a normalised action")
    return out[0], out[1]
