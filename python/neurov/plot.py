"""The run plots under their earlier name; they live in :mod:`neurov.plotting.runs`."""

from neurov.plotting.runs import adaptive_norm, control_inputs, dof_time, errors, save, xy_path

__all__ = ["adaptive_norm", "control_inputs", "dof_time", "errors", "save", "xy_path"]
