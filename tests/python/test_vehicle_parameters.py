"""VehicleParameters: the vehicle's parameters described once in C++
(config_fields beside the struct) and bound by the generic binder. Vehicle's
keyword arguments, properties and parameters(), and the vehicle files' keys,
all come from that one description."""

from __future__ import annotations

import copy
import pickle
from pathlib import Path
from typing import Any

import numpy as np
import pytest

import neurov
from neurov import errors
from neurov.config import vehicle_file
from neurov.config.vehicle_file import preset_path, read_vehicle_file

NAMES = [f["name"] for f in neurov.VehicleParameters.FIELDS]


def test_fields_name_every_vehicle_keyword_and_property() -> None:
    nerov = neurov.Vehicle.nerov()
    assert list(nerov.parameters()) == NAMES
    for name in NAMES:
        assert isinstance(getattr(type(nerov), name), property), name
        assert getattr(type(nerov), name).__doc__ == getattr(neurov.VehicleParameters, name).__doc__
    assert neurov.Vehicle(**nerov.parameters()).parameters().keys() == set(NAMES)


def test_fields_carry_unit_rule_shape_and_forms() -> None:
    rows = {f["name"]: f for f in neurov.VehicleParameters.FIELDS}
    assert (rows["mass"]["unit"], rows["mass"]["rule"], rows["mass"]["required"]) == ("kg", "> 0", True)
    assert (rows["inertia"]["shape"], rows["inertia"]["diagonal"], rows["inertia"]["rule"]) == ((3, 3), True, "finite")
    assert (rows["added_mass"]["shape"], rows["added_mass"]["diagonal"]) == ((6, 6), True)
    assert (rows["linear_damping"]["shape"], rows["linear_damping"]["rule"]) == ((6,), ">= 0")
    assert (rows["weight"]["rule"], rows["buoyancy"]["unit"]) == (">= 0", "N")
    required = [n for n in NAMES if rows[n]["required"]]
    assert required == ["mass", "inertia", "weight", "buoyancy", "added_mass", "linear_damping", "quadratic_damping"]
    assert "[kg m^2], finite" in (neurov.VehicleParameters.inertia.__doc__ or "")


def test_a_square_matrix_may_be_given_as_its_diagonal() -> None:
    p = neurov.VehicleParameters(inertia=[25.0, 50.0, 50.0], added_mass=np.diag([30.0, 80, 80, 15, 30, 30]))
    np.testing.assert_array_equal(p.inertia, np.diag([25.0, 50.0, 50.0]))
    np.testing.assert_array_equal(p.added_mass, np.diag([30.0, 80, 80, 15, 30, 30]))
    with pytest.raises(ValueError, match=r"VehicleParameters\.inertia' must have shape \(3, 3\) or its diagonal"):
        p.inertia = [1.0, 2.0]
    with pytest.raises(ValueError, match="VehicleParameters.coriolis_form' must be one of"):
        p.coriolis_form = "m2c"


def test_parameters_round_trip_through_the_struct() -> None:
    v = neurov.Vehicle.preset("bluerov2_heavy")
    p = neurov.VehicleParameters(**v.parameters())
    p.validate()
    assert p.coriolis_form == "velocity_independent"
    w = neurov.Vehicle(**{name: getattr(p, name) for name in NAMES})
    np.testing.assert_array_equal(v.mass_matrix(), w.mass_matrix())
    for q in (copy.deepcopy(p), pickle.loads(pickle.dumps(p))):
        assert repr(q) == repr(p)
    u = pickle.loads(pickle.dumps(w))
    np.testing.assert_array_equal(u.mass_matrix(), v.mass_matrix())


def test_the_struct_validates_with_the_vehicles_messages() -> None:
    p = neurov.VehicleParameters(**neurov.Vehicle.nerov().parameters())
    p.mass = 0.0
    with pytest.raises(errors.ValidationError, match=r"mass = 0: expected > 0 and finite") as info:
        p.validate()
    assert info.value.field == "mass"
    with pytest.raises(errors.ValidationError, match=r"mass = 0: expected > 0 and finite"):
        neurov.Vehicle(**{name: getattr(p, name) for name in NAMES})


def test_vehicle_keywords_are_checked_against_the_description() -> None:
    p = neurov.Vehicle.nerov().parameters()
    with pytest.raises(TypeError, match=r"unexpected keyword argument 'masss'; the parameters are mass, inertia"):
        neurov.Vehicle(**{**p, "masss": 1.0})
    del p["weight"]
    with pytest.raises(TypeError, match="missing required keyword argument 'weight'"):
        neurov.Vehicle(**p)
    # An optional field given None keeps its default; a required one may not be None.
    v = neurov.Vehicle(**{**neurov.Vehicle.nerov().parameters(), "centre_of_gravity": None})
    np.testing.assert_array_equal(v.centre_of_gravity, np.zeros(3))
    with pytest.raises(TypeError, match="'mass'"):
        neurov.Vehicle(**{**neurov.Vehicle.nerov().parameters(), "mass": None})


# ------------------------------------------------------------ the file reader


def test_the_file_readers_keys_are_the_fields_and_the_file_only_keys() -> None:
    table = vehicle_file.file_fields(neurov.VehicleParameters)
    assert set(table) == set(NAMES) | {"displaced_volume", "name", "source"}
    assert table["inertia"] == (True, ((3,), (3, 3)))
    assert table["coriolis_form"] == (False, ("str",))
    assert table["buoyancy"] == (False, ((),))  # or displaced_volume, checked apart
    assert vehicle_file._FIELDS == table


class _Extended(neurov.VehicleParameters):
    """The bound struct with one more described field, as C++ would add it."""

    FIELDS = neurov.VehicleParameters.FIELDS + (
        {"name": "ballast", "unit": "kg", "rule": ">= 0", "min": 0.0, "max": float("inf"), "doc": "Ballast.",
         "shape": (4,), "diagonal": False, "required": True},
    )
    ballast = np.zeros(4)


def test_a_field_added_to_the_description_is_read_from_files() -> None:
    table = vehicle_file.file_fields(_Extended)
    assert table["ballast"] == (True, ((4,),))
    assert set(table) - set(vehicle_file.file_fields(neurov.VehicleParameters)) == {"ballast"}


def test_a_vehicle_file_round_trips(tmp_path: Path) -> None:
    read = read_vehicle_file(preset_path("nerov"))
    v = read.vehicle()
    lines = [f"{k} = {np.asarray(x).tolist()!r}" if not isinstance(x, str) else f'{k} = "{x}"'
             for k, x in v.parameters().items()]
    path = tmp_path / "copy.toml"
    path.write_text("\n".join(lines).replace("'", '"') + "\n", encoding="utf-8")
    again = neurov.Vehicle.from_file(path)
    got: dict[str, Any] = again.parameters()
    for name, value in v.parameters().items():
        if isinstance(value, str):
            assert got[name] == value
        else:
            np.testing.assert_array_equal(got[name], value)
