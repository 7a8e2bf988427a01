"""The control laws a run can use, on the Python side.

- :mod:`neurov.laws.registry`: the built-in laws (the C++ list
  ``neurov._core.BUILT_IN_CONTROLLERS``) by their TOML type name, with what
  the builder fills in from the scenario.
- :mod:`neurov.laws.protocol`: what a law written in Python is (the
  :class:`neurov.Controller` protocol) and how one is called in a run.
- :mod:`neurov.laws.centres`: where the NN law's RBF centres go.
- :mod:`neurov.laws.weights`: the NN law's learnt weights in a file.

The laws themselves are C++ (``cpp/include/neurov/control``).
"""
