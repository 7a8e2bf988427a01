"""One error family: every error neurov raises for bad input is a
NeurovError (a ValueError), and a C++ validator's refusal carries its field
and index as attributes rather than only in its message."""

from __future__ import annotations

import importlib
import importlib.util
import inspect
import pkgutil

import pytest
import reference_model as ref

import neurov
from neurov import errors
from neurov.config.reading import scenario_from_mapping


def _neurov_modules():
    for info in pkgutil.walk_packages(neurov.__path__, "neurov."):
        if info.name.endswith("__main__"):  # importing it runs the command line
            continue
        if info.name.startswith("neurov.gym"):
            pytest.importorskip("gymnasium")
        # The Stable-Baselines3 adapter, the one module whose optional
        # dependency (SB3 and PyTorch) CI does not install: it is read where SB3 is.
        if info.name == "neurov.gym.sb3" and importlib.util.find_spec("stable_baselines3") is None:
            continue
        yield importlib.import_module(info.name)


def test_every_exception_class_in_the_package_is_a_neurov_error():
    found = {}
    for module in _neurov_modules():
        for name, obj in vars(module).items():
            if (inspect.isclass(obj) and issubclass(obj, BaseException)
                    and obj.__module__.startswith("neurov")):
                found[f"{obj.__module__}.{obj.__qualname__}"] = obj
    # Not errors of bad input: a warning; Ctrl-C during a study (a KeyboardInterrupt,
    # so that a caller's `except Exception` does not swallow it); and the machine's
    # failures (a full disk), which are OSErrors with their errno, as callers catch
    # them (Python cannot derive one class from both ValueError and OSError).
    refusals = {k: v for k, v in found.items()
                if not issubclass(v, (Warning, KeyboardInterrupt, OSError))}
    assert len(refusals) >= 8, sorted(found)
    outside = sorted(k for k, v in refusals.items() if not issubclass(v, errors.NeurovError))
    assert outside == []
    assert issubclass(errors.NeurovError, ValueError)


@pytest.mark.parametrize("name", errors.__all__)
def test_the_errors_module_lists_neurov_errors(name):
    cls = getattr(errors, name)
    if issubclass(cls, Warning):  # a run to be read with care, not a refusal
        assert issubclass(cls, RuntimeWarning)
    else:
        assert issubclass(cls, errors.NeurovError) and issubclass(cls, ValueError)
    assert getattr(neurov, name, cls) is cls


def test_a_refused_configuration_carries_its_field_and_index():
    config = neurov.PDConfig(kp=[1.0, 1.0, 1.0, -2.5, 1.0, 1.0], kd=[1.0] * 6)
    with pytest.raises(errors.ValidationError) as info:
        config.validate()
    e = info.value
    assert (e.field, e.index, e.value) == ("kp", 3, -2.5)
    assert e.expected and e.expected in str(e)
    assert isinstance(e, errors.NeurovError) and isinstance(e, ValueError)


def test_a_whole_matrix_refused_has_no_value_and_a_row_major_index():
    p = dict(ref.NEROV, inertia=[[25.0, 1.0, 0.0], [0.0, 50.0, 0.0], [0.0, 0.0, 50.0]])
    with pytest.raises(errors.ValidationError) as info:
        neurov.Vehicle(**p)
    assert info.value.field == "inertia"
    assert info.value.index in (1, 3)  # entry (0, 1) or (1, 0), row-major


def test_a_scenario_names_the_toml_key_from_the_attributes_not_the_message():
    mapping = {"duration": 1.0, "dt": 0.2, "controller": {"type": "pd", "kp": [1, 1, 1, 1, -1, 1]},
               "command": {"type": "square"}}
    with pytest.raises(errors.ScenarioError, match=r"controller\.kp\[4\] = -1: expected"):
        scenario_from_mapping(mapping, origin="t.toml")
