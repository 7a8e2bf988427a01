"""Every figure neurov draws, in one place.

- :mod:`neurov.plotting.runs`: one or more closed-loop runs (path, pose,
  errors, control inputs, adaptive norm); what ``neurov run --plot`` writes.
- :mod:`neurov.plotting.sea`: the sea a run met (the flow at the vehicle,
  the realised wave spectrum against the target); ``neurov run --plot``
  writes them for a scenario with a sea.
- :mod:`neurov.paper.figures`: the paper's Figs. 3-5 (``neurov paper``).
- :mod:`neurov.plotting.study`: a study's box plots and error bands
  (``neurov study``).
- :mod:`neurov.plotting.colours`: one colour per controller in every study figure.
- :mod:`neurov.plotting.labels`: what every figure calls things (thrusters
  T1 to Tn, each metric in words with its unit); :mod:`neurov.plotting.paths`:
  the start and direction marks of X-Y paths.

The run plots are also importable from here::

    from neurov import plotting
    plotting.save(plotting.xy_path([nn_result, linear_result]), "xy.png")
"""

from neurov.plotting.runs import adaptive_norm, control_inputs, dof_time, errors, save, xy_path

__all__ = ["adaptive_norm", "control_inputs", "dof_time", "errors", "save", "xy_path"]
