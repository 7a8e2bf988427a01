"""What every figure calls things: thruster names and the axis label (in
words, with its unit) of each run metric. One place, so that a figure, its
legend and a failure note never disagree.

Thrusters are numbered as a reader counts, T1 to Tn: T1 is the first column
of the vehicle file's thruster matrix, which scenario files and arrays index
as 0 (``thruster_failures`` ``index = 0``, the CSV column ``thrusts_0``).
"""

from __future__ import annotations

__all__ = ["METRIC_LABELS", "metric_label", "thruster_label"]


def thruster_label(index: int) -> str:
    """The figure name of the thruster at 0-based array `index`: ``T{index + 1}``."""
    if index < 0:
        raise ValueError(f"argument 'index' must be a 0-based thruster index >= 0, got {index}")
    return f"T{index + 1}"


_DOFS = (("x", "x (north)", "m"), ("y", "y (east)", "m"), ("z", "z (depth)", "m"),
         ("roll", "roll", "rad"), ("pitch", "pitch", "rad"), ("yaw", "yaw", "rad"))
_TAU = (("X", "N"), ("Y", "N"), ("Z", "N"), ("K", "N m"), ("M", "N m"), ("N", "N m"))

#: Each run metric (a column of a study's runs table) as an axis label: what
#: it is in words, then its unit in brackets. The mean and maximum of ``|tau|``
#: over all six DOFs, and the control energy, add forces and moments, hence
#: "N, N m". The adapted parameters (NN weights or theta_hat) carry the units
#: of different regressor columns: their norm has none of its own.
METRIC_LABELS: dict[str, str] = {
    "rmse_position_m": "RMS position error [m]",
    "max_position_error_m": "max position error [m]",
    "rmse_yaw_rad": "RMS yaw error [rad]",
    "max_yaw_error_rad": "max yaw error [rad]",
    **{f"rmse_{k}": f"RMS {name} error [{unit}]" for k, name, unit in _DOFS},
    **{f"max_abs_error_{k}": f"max |{name} error| [{unit}]" for k, name, unit in _DOFS},
    **{f"iae_{k}": f"integral of |{name} error| [{unit} s]" for k, name, unit in _DOFS},
    "mean_abs_tau": "mean |τ| over the six DOFs [N, N m]",
    "max_abs_tau": "max |τ| over the six DOFs [N, N m]",
    **{f"mean_abs_tau_dof_{i}": f"mean |τ {name}| [{unit}]" for i, (name, unit) in enumerate(_TAU)},
    **{f"max_abs_tau_dof_{i}": f"max |τ {name}| [{unit}]" for i, (name, unit) in enumerate(_TAU)},
    "control_energy": "control effort ∫‖τ‖ dt [N s, N m s]",
    "final_adaptive_norm": "final norm of the adapted parameters [mixed units]",
    "max_adaptive_norm": "max norm of the adapted parameters [mixed units]",
    "refused_steps": "refused control steps [count]",
    "diverged": "run diverged [0 or 1]",
}


def metric_label(key: str) -> str:
    """The axis label of metric `key`; the key itself for a metric without one."""
    return METRIC_LABELS.get(key, key)
