"""Shared fixtures for neurov's Python tests."""

from __future__ import annotations

import os
import sys
from pathlib import Path
from typing import Any

import numpy as np
import pytest

# reference_model.py sits next to this file; make it importable whatever
# pytest's import mode is.
sys.path.insert(0, str(Path(__file__).resolve().parent))

import neurov  # noqa: E402
import reference_model as ref  # noqa: E402


@pytest.fixture
def rng() -> np.random.Generator:
    """A fresh generator with a fixed seed: every test sees the same points."""
    return np.random.default_rng(20240607)


@pytest.fixture
def nerov() -> neurov.Vehicle:
    return neurov.Vehicle.nerov()


@pytest.fixture(params=["velocity_independent", "kirchhoff"])
def coriolis_form(request: pytest.FixtureRequest) -> str:
    return str(request.param)


@pytest.fixture
def general_parameters(coriolis_form: str) -> dict[str, Any]:
    return ref.general_parameters(coriolis_form)


@pytest.fixture
def general_vehicle(general_parameters: dict[str, Any]) -> neurov.Vehicle:
    return neurov.Vehicle(**general_parameters)


@pytest.fixture
def user_controllers_importable(monkeypatch: pytest.MonkeyPatch) -> None:
    """The package of the tests' own controllers (user_controllers/, beside
    this file) importable here and in every worker process a study starts."""
    here = str(Path(__file__).resolve().parent)
    monkeypatch.syspath_prepend(here)
    monkeypatch.setenv("PYTHONPATH", os.pathsep.join([here, os.environ.get("PYTHONPATH", "")]))
