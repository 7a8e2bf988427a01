"""Argument checking of every public function that takes arrays or numbers:
a wrong shape, dtype or a non-finite value is an error that names the
argument; every reasonable array-like is accepted and gives the same result."""

from __future__ import annotations

import fractions
from typing import Any, Callable

import numpy as np
import pytest

import neurov
import reference_model as ref
from bad_input_sites import (ARRAY_CASES, EXPECTED_SHAPE, GOOD, INTEGER, NUMBER_ALSO_OK, SITE, SITES, VEHICLE, Site,
                             comparable, wrong_shapes)


# ------------------------------------------------------------- array arguments


@pytest.mark.parametrize(("site", "arg"), ARRAY_CASES)
def test_wrong_shape(site: Site, arg: str) -> None:
    for shape in wrong_shapes(np.asarray(GOOD[arg])):
        with pytest.raises(ValueError) as err:
            site.call(**{arg: np.ones(shape)})
        message = str(err.value)
        assert f"'{arg}'" in message, message
        assert EXPECTED_SHAPE[arg] in message, message
        assert f"got {shape}" in message, message


@pytest.mark.parametrize(("site", "arg"), ARRAY_CASES)
def test_python_scalar_for_an_array_is_a_shape_error(site: Site, arg: str) -> None:
    if arg in NUMBER_ALSO_OK:
        np.testing.assert_array_equal(
            comparable(site.call(**{arg: 2.0})), comparable(site.call(**{arg: np.full(np.shape(GOOD[arg]), 2.0)}))
        )
        return
    with pytest.raises(ValueError, match=f"'{arg}'.*must have shape"):
        site.call(**{arg: 1.0})


@pytest.mark.parametrize(("site", "arg"), ARRAY_CASES)
def test_wrong_dtype(site: Site, arg: str) -> None:
    good = np.asarray(GOOD[arg])
    bad_values = {
        "str array": np.full(good.shape, "a"),
        "str list": np.full(good.shape, "1.0").tolist(),
        "str": "abcdef",
        "complex": good.astype(complex),
        "object": good.astype(object),
        "bool": np.ones(good.shape, dtype=bool),
        "dict": {"a": 1},
        "object()": object(),
        "bytes": b"\x00" * 48,
    }
    for what, bad in bad_values.items():
        with pytest.raises(TypeError) as err:
            site.call(**{arg: bad})
        assert f"'{arg}'" in str(err.value), (what, str(err.value))


@pytest.mark.parametrize(("site", "arg"), ARRAY_CASES)
def test_none(site: Site, arg: str) -> None:
    if arg in site.optional:
        # None is the default: the same as leaving the argument out.
        kwargs = {k: GOOD[k] for k in site.args if k != arg}
        kwargs.update(site.fixed)
        np.testing.assert_array_equal(comparable(site.call(**{arg: None})), comparable(site.func(**kwargs)))
    else:
        with pytest.raises(TypeError, match=f"'{arg}'.*None"):
            site.call(**{arg: None})


@pytest.mark.parametrize(("site", "arg"), ARRAY_CASES)
def test_non_finite(site: Site, arg: str) -> None:
    good = np.asarray(GOOD[arg], dtype=float)
    for bad in (np.nan, np.inf, -np.inf):
        for index in (0, good.size - 1):
            value = good.copy()
            value.flat[index] = bad
            with pytest.raises(ValueError, match=f"'{arg}'.*finite"):
                site.call(**{arg: value})
            with pytest.raises(ValueError, match=f"'{arg}'.*finite"):
                site.call(**{arg: value.tolist()})


def accepted_forms(good: np.ndarray) -> dict[str, Any]:
    strided = np.zeros(good.shape[:-1] + (2 * good.shape[-1],))
    strided[..., ::2] = good
    view = strided[..., ::2]
    assert not view.flags.c_contiguous
    reversed_ = good[::-1].copy()[::-1]
    readonly = good.copy()
    readonly.flags.writeable = False
    forms = {
        "list": good.tolist(),
        "tuple": tuple(good.tolist()),
        "strided view": view,
        "negative strides": reversed_,
        "read-only": readonly,
        "read-only strided": np.lib.stride_tricks.as_strided(view, writeable=False),
        "big-endian": good.astype(">f8"),
    }
    if good.ndim == 2:
        forms["fortran order"] = np.asfortranarray(good)
        forms["transposed view"] = good.T.copy().T
    return forms


@pytest.mark.parametrize(("site", "arg"), ARRAY_CASES)
def test_array_likes_are_accepted_and_agree(site: Site, arg: str) -> None:
    good = np.asarray(GOOD[arg], dtype=float)
    expected = comparable(site.call(**{arg: good}))
    for what, value in accepted_forms(good).items():
        before = np.array(value, copy=True)
        got = comparable(site.call(**{arg: value}))
        np.testing.assert_array_equal(got, expected, err_msg=what)
        np.testing.assert_array_equal(np.asarray(value), before, err_msg=f"{what} was modified")


@pytest.mark.parametrize(("site", "arg"), ARRAY_CASES)
def test_integer_and_float32_arrays_are_accepted(site: Site, arg: str) -> None:
    ints = INTEGER[arg]
    expected = comparable(site.call(**{arg: ints.astype(float)}))
    for dtype in (np.int64, np.int32, np.int16):
        got = comparable(site.call(**{arg: ints.astype(dtype)}))
        np.testing.assert_array_equal(got, expected, err_msg=str(dtype))
    np.testing.assert_array_equal(comparable(site.call(**{arg: ints.tolist()})), expected)
    good32 = np.asarray(GOOD[arg]).astype(np.float32)
    np.testing.assert_array_equal(
        comparable(site.call(**{arg: good32})), comparable(site.call(**{arg: good32.astype(np.float64)}))
    )


def test_array_results_are_fresh_writeable_float64() -> None:
    for site in SITES:
        result = site.call()
        arrays = result if isinstance(result, tuple) else (result,)
        for a in arrays:
            if isinstance(a, np.ndarray):
                assert a.dtype == np.float64 and a.flags.writeable, site.name
                assert not any(np.shares_memory(a, GOOD[k]) for k in site.args if isinstance(GOOD[k], np.ndarray))


# ------------------------------------------------------------ scalar arguments

SCALAR_CASES = [
    pytest.param(lambda **kw: neurov.rotation(**{"phi": 0.1, "theta": -0.2, "psi": 0.3, **kw}), "phi", id="rotation-phi"),
    pytest.param(lambda **kw: neurov.rotation(**{"phi": 0.1, "theta": -0.2, "psi": 0.3, **kw}), "theta", id="rotation-theta"),
    pytest.param(lambda **kw: neurov.rotation(**{"phi": 0.1, "theta": -0.2, "psi": 0.3, **kw}), "psi", id="rotation-psi"),
    pytest.param(lambda **kw: SITE["rk4_step"].call(**{"dt": 0.1, **kw}), "dt", id="rk4_step-dt"),
    pytest.param(lambda **kw: SITE["Vehicle"].call(**kw), "mass", id="Vehicle-mass"),
    pytest.param(lambda **kw: SITE["Vehicle"].call(**kw), "weight", id="Vehicle-weight"),
    pytest.param(lambda **kw: SITE["Vehicle"].call(**kw), "buoyancy", id="Vehicle-buoyancy"),
]


@pytest.mark.parametrize(("call", "arg"), SCALAR_CASES)
def test_scalar_wrong_type(call: Callable[..., Any], arg: str) -> None:
    for bad in (None, "1.0", True, False, 1j, [1.0], (1.0,), {"x": 1.0}, object()):
        with pytest.raises(TypeError, match=f"'{arg}'"):
            call(**{arg: bad})


@pytest.mark.parametrize(("call", "arg"), SCALAR_CASES)
def test_scalar_given_a_one_element_array(call: Callable[..., Any], arg: str) -> None:
    with pytest.raises(TypeError, match=f"'{arg}'"):
        call(**{arg: np.array([1.0])})


@pytest.mark.parametrize(("call", "arg"), SCALAR_CASES)
def test_scalar_non_finite(call: Callable[..., Any], arg: str) -> None:
    for bad in (np.nan, np.inf, -np.inf, float("nan"), np.float32("nan")):
        with pytest.raises(ValueError, match=f"'{arg}'.*finite"):
            call(**{arg: bad})


@pytest.mark.parametrize(("call", "arg"), SCALAR_CASES)
def test_scalar_number_types_are_accepted(call: Callable[..., Any], arg: str) -> None:
    value = {"phi": 1, "theta": -1, "psi": 2, "dt": 1, "mass": 185, "weight": 1815, "buoyancy": 1790}[arg]
    expected = comparable(call(**{arg: float(value)}))
    for form in (
        value,
        np.int64(value),
        np.int32(value),
        np.float64(value),
        np.float32(value),
        np.array(float(value)),
        fractions.Fraction(value),
    ):
        np.testing.assert_array_equal(comparable(call(**{arg: form})), expected, err_msg=repr(form))


@pytest.mark.parametrize("dt", [0, 0.0, -0.0, -0.1, -np.inf, np.inf, np.nan])
def test_rk4_step_bad_dt(dt: float) -> None:
    with pytest.raises(ValueError, match="'dt'"):
        neurov.rk4_step(VEHICLE, GOOD["eta"], GOOD["nu"], GOOD["tau"], dt)


@pytest.mark.parametrize("dt", [True, False, None, "0.1", 0.1j])
def test_rk4_step_dt_of_wrong_type(dt: Any) -> None:
    with pytest.raises(TypeError, match="'dt'"):
        neurov.rk4_step(VEHICLE, GOOD["eta"], GOOD["nu"], GOOD["tau"], dt)


def test_rk4_step_needs_a_vehicle() -> None:
    for bad in (None, neurov.Vehicle.nerov().parameters(), "nerov"):
        with pytest.raises(TypeError, match="vehicle"):
            neurov.rk4_step(bad, GOOD["eta"], GOOD["nu"], GOOD["tau"], 0.1)  # type: ignore[arg-type]


# ---------------------------------------------------- Vehicle(...) parameters

BAD_VEHICLE_VALUES = {
    "zero mass": ("mass", 0.0),
    "negative mass": ("mass", -1.0),
    "negative weight": ("weight", -1.0),
    "negative buoyancy": ("buoyancy", -0.5),
    "non-symmetric inertia": ("inertia", [[25.0, 1.0, 0.0], [0.0, 50.0, 0.0], [0.0, 0.0, 50.0]]),
    "indefinite inertia": ("inertia", [-100.0, 50.0, 50.0]),
    "non-symmetric added_mass": ("added_mass", np.triu(np.full((6, 6), 5.0)) + np.eye(6) * 30),
    "indefinite added_mass": ("added_mass", np.full(6, -1000.0)),
    "negative linear_damping": ("linear_damping", [70.0, 100.0, -1.0, 30.0, 50.0, 50.0]),
    "negative quadratic_damping": ("quadratic_damping", [-100.0, 200.0, 200.0, 50.0, 100.0, 100.0]),
    "off-centre gravity": ("centre_of_gravity", [0.0, 0.0, 5.0]),  # M_RB indefinite
    "unknown coriolis_form": ("coriolis_form", "m2c"),
    "empty coriolis_form": ("coriolis_form", ""),
}


@pytest.mark.parametrize("case", list(BAD_VEHICLE_VALUES))
def test_vehicle_bad_parameter(case: str) -> None:
    key, value = BAD_VEHICLE_VALUES[case]
    p = ref.general_parameters()
    p[key] = value
    with pytest.raises(ValueError) as err:
        neurov.Vehicle(**p)
    assert key in str(err.value), str(err.value)


def test_vehicle_negative_inertia_is_refused() -> None:
    p = dict(ref.NEROV, inertia=[-1.0, 50.0, 50.0])  # M[3, 3] = -1 + 15 > 0
    with pytest.raises(ValueError, match="inertia"):
        neurov.Vehicle(**p)


def test_vehicle_coriolis_form_must_be_a_string() -> None:
    with pytest.raises(TypeError, match="'coriolis_form'"):
        neurov.Vehicle(**dict(ref.NEROV, coriolis_form=1))


def test_vehicle_unknown_or_missing_keyword() -> None:
    with pytest.raises(TypeError, match="masss"):
        neurov.Vehicle(**dict(ref.NEROV, masss=1.0))
    p = dict(ref.NEROV)
    del p["mass"]
    with pytest.raises(TypeError):
        neurov.Vehicle(**p)
    with pytest.raises(TypeError):
        neurov.Vehicle(185.0)  # type: ignore[call-arg]


def test_vehicle_error_leaves_nothing_half_built() -> None:
    """A failed build raises; the presets are unaffected."""
    with pytest.raises(ValueError):
        neurov.Vehicle(**dict(ref.NEROV, mass=-1.0))
    assert neurov.Vehicle.nerov().mass == 185.0
