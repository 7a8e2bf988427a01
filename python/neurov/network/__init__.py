"""Where the NN controller's network puts its centres, beyond the boxes of
:mod:`neurov.centres`: :func:`~neurov.network.path_centres.along_path`."""

from neurov.network.path_centres import along_path, path_inputs

__all__ = ["along_path", "path_inputs"]
