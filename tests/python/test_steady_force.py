"""The steady force (sim/disturbances/steady_force.hpp), read from a
scenario file's [steady_force] table by the one reader of the disturbance
parts (neurov/config/sea.py): its keys, its force in body axes with its
moment, and its errors named by file and TOML key."""

from __future__ import annotations

import copy
import sys

import numpy as np
import pytest

from neurov import _core
from neurov.config.reading import scenario_from_mapping
from neurov.config.scenario import ScenarioError
from neurov.running.simulation import simulate
from neurov.study.spec import SCENARIO_DIR

if sys.version_info >= (3, 11):
    import tomllib
else:  # pragma: no cover
    import tomli as tomllib

BASE = tomllib.loads((SCENARIO_DIR / "nerov_square.toml").read_text())


def facing_east(table: str):
    """A vehicle held at 10 m facing east for 0.2 s, with the TOML `table` added."""
    data = copy.deepcopy(BASE)
    data.update({"duration": 0.2, "initial": {"eta": [0, 0, 10, 0, 0, np.pi / 2]},
                 "command": {"type": "waypoints", "times": [0.0], "poses": [[0, 0, 10, 0, 0, np.pi / 2]]},
                 "controller": {"type": "pd"}})
    data.pop("disturbances", None)
    data.update(tomllib.loads(table))
    return scenario_from_mapping(data, "drift.toml")


def test_the_table_is_read_into_the_core_struct_and_pushes_in_body_axes() -> None:
    s = facing_east("[steady_force]\nforce = [100.0, 0.0, 0.0]\npoint = [0.5, 0.0, 0.0]\n")
    f = s.simulation.steady_force
    assert isinstance(f, _core.SteadyForceConfig)
    np.testing.assert_array_equal(f.force, [100.0, 0.0, 0.0])
    assert f.start == 0.0  # the C++ default
    # Facing east, the northward force pushes to the left (body -y) and, 0.5 m
    # ahead of the origin, yaws the vehicle to the left.
    np.testing.assert_allclose(simulate(s).disturbance[0], [0, -100, 0, 0, 0, -50], atol=1e-9)


def test_without_the_table_there_is_no_force_and_the_description_is_as_before() -> None:
    s = facing_east("")
    assert s.simulation.steady_force is None
    assert "steady_force" not in s.describe()["simulation"]
    assert np.abs(simulate(s).disturbance[0]).max() == 0.0


@pytest.mark.parametrize(("table", "message"), [
    ("[steady_force]\nforse = [1.0, 0.0, 0.0]\n",
     r"drift\.toml: steady_force\.forse: unknown field; did you mean 'force'\?"),
    ("[steady_force]\nstart = -1.0\n", r"drift\.toml: steady_force\.start = -1: expected >= 0 and finite"),
    ("[steady_force]\nforce = [1.0, 2.0]\n", r"drift\.toml: steady_force\.force: expected 3 numbers"),
    ("[steady_force]\nstart = \"now\"\n", r"drift\.toml: steady_force\.start: expected a number, got str"),
])
def test_bad_tables_are_named_by_file_and_key(table: str, message: str) -> None:
    with pytest.raises(ScenarioError, match=message):
        facing_east(table)
