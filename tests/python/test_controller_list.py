"""The one list of built-in controllers (neurov/control/built_in_controllers.hpp):
the registry, the all-C++ loop's classes and neurov's exports all come from
``neurov._core.BUILT_IN_CONTROLLERS``, so every controller of the list is in
each, builds from its defaults on a scenario, runs in C++ and snapshots."""

from __future__ import annotations

import importlib.resources
import pickle
from pathlib import Path

import numpy as np
import pytest

import neurov
from neurov import _core
from neurov.laws.protocol import BUILT_IN_CONTROLLERS, is_built_in
from neurov.laws.registry import REGISTRY, build_controller

NAMES = list(_core.BUILT_IN_CONTROLLERS)
SQUARE = importlib.resources.files("neurov") / "scenarios" / "nerov_square.toml"


def test_the_list_is_the_registry_the_loop_and_the_exports() -> None:
    assert list(REGISTRY) == NAMES
    assert BUILT_IN_CONTROLLERS == tuple(_core.BUILT_IN_CONTROLLERS.values())
    for name, cls in _core.BUILT_IN_CONTROLLERS.items():
        assert cls.type_name == name
        assert REGISTRY[name].config is cls.Config
        assert REGISTRY[name].title == cls.title
        assert getattr(neurov, cls.__name__) is cls and cls.__name__ in neurov.__all__
        assert getattr(neurov, cls.Config.__name__) is cls.Config and cls.Config.__name__ in neurov.__all__


@pytest.mark.parametrize("name", NAMES)
def test_each_builds_runs_in_cpp_and_snapshots(name: str) -> None:
    scenario = neurov.load_scenario(SQUARE).replace(duration=2.0)
    spec = neurov.ControllerSpec(name)
    ctl = build_controller(spec, scenario)
    assert is_built_in(ctl) and type(ctl) is _core.BUILT_IN_CONTROLLERS[name]
    result = neurov.simulate(scenario, spec)
    assert np.isfinite(result.tau_demanded).all() and not result.diverged
    twin = pickle.loads(pickle.dumps(ctl))
    u = (np.full(6, 0.1), np.full(6, 0.05), np.zeros(6), np.zeros(6), np.zeros(6))
    assert ctl.step(*u).tobytes() == twin.step(*u).tobytes()


@pytest.mark.parametrize("name", NAMES)
def test_each_reads_from_a_scenario_file_with_its_defaults(name: str, tmp_path: Path) -> None:
    """A file gives only the type: the fields the builder fills from the
    scenario (dt, the nominal theta or vehicle) are checked beside stand-ins,
    not refused as the struct's empty defaults."""
    path = tmp_path / "s.toml"
    path.write_text(f'name = "t"\nduration = 1.0\n[command]\ntype = "square"\nside = 4.0\n'
                    f'[controller]\ntype = "{name}"\n', encoding="utf-8")
    scenario = neurov.load_scenario(path)
    assert scenario.controller.type == name
    assert type(build_controller(scenario.controller, scenario)) is _core.BUILT_IN_CONTROLLERS[name]
