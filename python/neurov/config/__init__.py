"""What a run is, before it runs: the configuration layer.

- :mod:`neurov.config.scenario`: the :class:`neurov.Scenario` dataclass and
  where shipped scenarios are found (:func:`neurov.load_scenario`).
- :mod:`neurov.config.reading`: a scenario file (TOML) read into a scenario;
  :mod:`neurov.config.sea` and :mod:`neurov.config.realism` read its sea
  (current, waves, payload, tether) and its realism keys (timing, sensors).
- :mod:`neurov.schema` (a foundation, beneath this layer and the laws): a
  TOML value moved into a field of a C++ config struct.
- :mod:`neurov.config.vehicle_file`: vehicle files.
- :mod:`neurov.config.trajectories`: commanded trajectories r(t).
"""
