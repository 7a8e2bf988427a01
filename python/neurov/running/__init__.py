"""Runs: a scenario and a controller made into a closed loop, and run.

- :mod:`neurov.running.closed_loop`: the one place that chooses the loop (the
  C++ loop for a built-in controller, :class:`neurov.Simulator` stepping a
  Python one).
- :mod:`neurov.running.simulation`: :func:`neurov.simulate`.
- :mod:`neurov.running.many`: :func:`neurov.simulate_many`, the one place
  that chooses how a list of runs goes (C++ batches, a batched Python
  policy's batches, run by run); a study's batches come here too.
- :mod:`neurov.running.stepper`: :class:`neurov.Simulator`, a run stepped
  from Python one control period per call.
- :mod:`neurov.running.plant`: the vehicle and the checked core config a
  scenario describes.
- :mod:`neurov.running.stream`: a run streamed chunk by chunk into its files.
- :mod:`neurov.running.folder`: the output folder of one run.
- :mod:`neurov.running.command`: ``neurov run SCENARIO.toml``.
"""
