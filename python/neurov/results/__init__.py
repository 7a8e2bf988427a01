"""What a run gives: the results layer.

- :mod:`neurov.results.timeseries`: :class:`neurov.Result`, a run's series
  as arrays, with its metrics and its export.
- :mod:`neurov.results.columns`: the series as named table columns (CSV,
  Parquet, pandas), from the C++ table of series.
- :mod:`neurov.results.metrics`: every metric, defined once.
- :mod:`neurov.results.export`: the CSV and NPZ writers.
- :mod:`neurov.results.load`: a run read back (:func:`neurov.load_result`).
- :mod:`neurov.results.decimation`: the rows a figure draws of a long run.
"""
