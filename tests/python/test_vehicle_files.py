"""Vehicle TOML files: the shipped presets and every way a file can be wrong."""

from __future__ import annotations

import re
from pathlib import Path
from typing import Any

import numpy as np
import pytest

import neurov
import reference_model as ref
from neurov.config import vehicle_file

GOOD = """\
name = "test vehicle"
mass = 185.0
inertia = [25.0, 50.0, 50.0]
centre_of_gravity = [0.0, 0.0, 0.0]
centre_of_buoyancy = [0.0, 0.0, -0.02]
weight = 1800.0
buoyancy = 1800.0
added_mass = [30.0, 80.0, 80.0, 15.0, 30.0, 30.0]
linear_damping = [70.0, 100.0, 100.0, 30.0, 50.0, 50.0]
quadratic_damping = [100.0, 200.0, 200.0, 50.0, 100.0, 100.0]
"""


def write(tmp_path: Path, text: str, name: str = "vehicle.toml") -> Path:
    path = tmp_path / name
    path.write_text(text, encoding="utf-8")
    return path


def replace_line(key: str, new: str | None) -> str:
    """GOOD with the line of `key` replaced by `new` (None drops it)."""
    lines = GOOD.splitlines()
    hits = [i for i, line in enumerate(lines) if line.startswith(f"{key} =")]
    assert len(hits) == 1, key
    if new is None:
        del lines[hits[0]]
    else:
        lines[hits[0]] = new
    return "\n".join(lines) + "\n"


def assert_same_vehicle(a: neurov.Vehicle, b: neurov.Vehicle) -> None:
    pa, pb = a.parameters(), b.parameters()
    assert pa.keys() == pb.keys()
    for key in pa:
        value_a: Any = pa[key]  # type: ignore[literal-required]
        value_b: Any = pb[key]  # type: ignore[literal-required]
        if isinstance(value_a, np.ndarray):
            np.testing.assert_array_equal(value_a, value_b, err_msg=key)
        else:
            assert value_a == value_b, key


# ------------------------------------------------------------------ presets


def test_nerov_file_is_the_builtin_nerov() -> None:
    path = vehicle_file.preset_path("nerov")
    assert_same_vehicle(neurov.Vehicle.from_file(path), neurov.Vehicle.nerov())
    assert_same_vehicle(neurov.Vehicle.preset("nerov"), neurov.Vehicle.nerov())
    assert_same_vehicle(neurov.Vehicle(**ref.NEROV), neurov.Vehicle.nerov())


def test_preset_names() -> None:
    names = vehicle_file.preset_names()
    assert {"nerov", "bluerov2_heavy"} <= set(names)
    assert names == sorted(names)


@pytest.mark.parametrize("name", vehicle_file.preset_names())
def test_every_preset_loads(name: str) -> None:
    path = vehicle_file.preset_path(name)
    assert path.is_file()
    for vehicle in (
        neurov.Vehicle.preset(name),
        neurov.Vehicle.from_file(path),
        neurov.Vehicle.from_file(str(path)),
        vehicle_file.load_vehicle(path),
    ):
        assert isinstance(vehicle, neurov.Vehicle)
        assert np.linalg.eigvalsh(vehicle.mass_matrix()).min() > 0
        assert vehicle.mass > 0
    assert_same_vehicle(neurov.Vehicle.preset(name), neurov.Vehicle(**vehicle_file.load_vehicle_parameters(path)))


def test_unknown_preset() -> None:
    with pytest.raises(ValueError, match="nerov") as err:
        neurov.Vehicle.preset("nerv")
    assert "'nerv'" in str(err.value)


# ----------------------------------------------------------- good variations


def test_good_file_loads(tmp_path: Path) -> None:
    assert_same_vehicle(neurov.Vehicle.from_file(write(tmp_path, GOOD)), neurov.Vehicle.nerov())


def test_full_matrices_integers_and_other_tables_are_accepted(tmp_path: Path) -> None:
    text = replace_line("inertia", "inertia = [[25, 0, 0], [0, 50, 0], [0, 0, 50]]")
    added = np.diag([30, 80, 80, 15, 30, 30]).tolist()
    text = text.replace("added_mass = [30.0, 80.0, 80.0, 15.0, 30.0, 30.0]", f"added_mass = {added}")
    text = text.replace("mass = 185.0", "mass = 185")
    text += ('coriolis_form = "velocity_independent"\nsource = "a test"\n\n[thrusters]\n'
             'positions = [[1, 0, 0]]\ndirections = [[1, 0, 0]]\nmax_thrust = 100\n')
    assert_same_vehicle(neurov.Vehicle.from_file(write(tmp_path, text)), neurov.Vehicle.nerov())


def test_a_typo_in_thrusters_is_an_error_even_when_no_scenario_uses_them(tmp_path: Path) -> None:
    """The whole file is checked on every read: a misspelt [thrusters] key
    used to pass until a scenario switched thrusters on."""
    text = GOOD + "\n[thrusters]\npositions = [[1, 0, 0]]\ndirections = [[1, 0, 0]]\nmax_thust = 100\n"
    path = write(tmp_path, text)
    with pytest.raises(neurov.VehicleFileError, match=r"thrusters\.max_thust: unknown field; did you mean 'max_thrust'"):
        neurov.Vehicle.from_file(path)
    scenario = tmp_path / "s.toml"
    scenario.write_text(f'[vehicle]\nfile = "{path.name}"\nthrusters = false\n'
                        '[command]\ntype = "square"\n[controller]\ntype = "pd"\nkp = 1\n')
    with pytest.raises(neurov.ScenarioError, match=r"s\.toml: vehicle: .*max_thust"):
        neurov.load_scenario(scenario)


def test_optional_fields_default_to_zero(tmp_path: Path) -> None:
    text = replace_line("centre_of_gravity", None)
    text = text.replace("centre_of_buoyancy = [0.0, 0.0, -0.02]\n", "")
    assert "centre_of" not in text
    v = neurov.Vehicle.from_file(write(tmp_path, text))
    np.testing.assert_array_equal(v.centre_of_gravity, np.zeros(3))
    np.testing.assert_array_equal(v.centre_of_buoyancy, np.zeros(3))
    assert v.coriolis_form == "velocity_independent"


def test_kirchhoff_form_from_file(tmp_path: Path) -> None:
    v = neurov.Vehicle.from_file(write(tmp_path, GOOD + 'coriolis_form = "kirchhoff"\n'))
    assert v.coriolis_form == "kirchhoff"


# --------------------------------------------------------------- bad files

def bad_value(key: str, value: str, detail: str) -> tuple[str, str, str]:
    """A BAD_FILES case: GOOD with `key = value`, the message naming `key` and holding `detail`."""
    return replace_line(key, f"{key} = {value}"), key, detail


BAD_FILES = {
    # case: (file text, field the message must name, further text it must hold)
    "missing field": (replace_line("mass", None), "mass", "missing"),
    "missing damping": (replace_line("linear_damping", None), "linear_damping", "missing"),
    "misspelt field": (replace_line("mass", "mas = 185.0"), "mass", "did you mean"),
    "misspelt damping": (
        replace_line("linear_damping", "linear_dampin = [70.0, 100.0, 100.0, 30.0, 50.0, 50.0]"),
        "linear_damping",
        "did you mean",
    ),
    "string for mass": bad_value("mass", '"heavy"', "a number"),
    "bool for mass": bad_value("mass", "true", "a number"),
    "list for mass": bad_value("mass", "[185.0]", "a number"),
    "five damping entries": bad_value("linear_damping", "[70.0, 100.0, 100.0, 30.0, 50.0]", "6"),
    "string in damping": bad_value("quadratic_damping", '[100.0, 200.0, "x", 50.0, 100.0, 100.0]', "6"),
    "ragged inertia": bad_value("inertia", "[[25.0, 0.0, 0.0], [0.0, 50.0], [0.0, 0.0, 50.0]]", "3"),
    "infinite mass": bad_value("mass", "inf", "finite"),
    "nan inertia": bad_value("inertia", "[25.0, nan, 50.0]", "finite"),
    "infinite centre of buoyancy": bad_value("centre_of_buoyancy", "[0.0, 0.0, -inf]", "finite"),
    "negative mass": bad_value("mass", "-185.0", "> 0"),
    "zero mass": bad_value("mass", "0.0", "> 0"),
    "negative weight": bad_value("weight", "-1.0", ">= 0"),
    "negative damping": bad_value("quadratic_damping", "[100.0, 200.0, 200.0, 50.0, -100.0, 100.0]", ">= 0"),
    "non-symmetric inertia": bad_value(
        "inertia", "[[25.0, 1.0, 0.0], [0.0, 50.0, 0.0], [0.0, 0.0, 50.0]]", "symmetric"
    ),
    "indefinite added mass": bad_value(
        "added_mass", "[-300.0, 80.0, 80.0, 15.0, 30.0, 30.0]", "positive semidefinite"
    ),
    "bad coriolis form": (GOOD + 'coriolis_form = "m2c"\n', "coriolis_form", "kirchhoff"),
    "number for coriolis form": (GOOD + "coriolis_form = 1\n", "coriolis_form", "string"),
    "number for name": bad_value("name", "3", "string"),
}


@pytest.mark.parametrize("case", list(BAD_FILES))
def test_bad_file(tmp_path: Path, case: str) -> None:
    text, field, detail = BAD_FILES[case]
    assert text != GOOD
    path = write(tmp_path, text)
    for load in (neurov.Vehicle.from_file, vehicle_file.load_vehicle):
        with pytest.raises(neurov.VehicleFileError) as err:
            load(path)
        message = str(err.value)
        assert isinstance(err.value, ValueError)
        assert str(path) in message
        assert re.search(rf"\b{field}\b", message), message
        assert detail in message, message


def test_misspelt_field_suggests_the_right_name(tmp_path: Path) -> None:
    path = write(tmp_path, replace_line("buoyancy", "bouyancy = 1800.0"))
    with pytest.raises(neurov.VehicleFileError, match=r"'bouyancy'.*did you mean 'buoyancy'\?"):
        neurov.Vehicle.from_file(path)


def test_invalid_toml(tmp_path: Path) -> None:
    path = write(tmp_path, GOOD + "mass == 3\n")
    with pytest.raises(neurov.VehicleFileError, match="TOML") as err:
        neurov.Vehicle.from_file(path)
    assert str(path) in str(err.value)
    assert "line 11" in str(err.value)


def test_duplicate_key_is_invalid_toml(tmp_path: Path) -> None:
    path = write(tmp_path, GOOD + "mass = 3.0\n")
    with pytest.raises(neurov.VehicleFileError, match="TOML") as err:
        neurov.Vehicle.from_file(path)
    assert str(path) in str(err.value)


def test_missing_file(tmp_path: Path) -> None:
    path = tmp_path / "no_such_vehicle.toml"
    with pytest.raises(neurov.VehicleFileError, match="no such vehicle file") as err:
        neurov.Vehicle.from_file(path)
    assert str(path) in str(err.value)


def test_vehicle_file_error_is_a_value_error() -> None:
    assert issubclass(neurov.VehicleFileError, ValueError)
    assert neurov.VehicleFileError is vehicle_file.VehicleFileError
