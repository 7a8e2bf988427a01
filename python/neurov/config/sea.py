"""Reading the sea of a scenario file: ``[current] model = "gauss_markov"``
and the table of every disturbance part that has one (``[waves]``,
``[[payload]]``, ``[tether]``, ...: ``neurov.DISTURBANCE_TABLES``, in the
order of the parts in C++; docs/disturbances.md).

Each value goes into the core's own struct (``GaussMarkovCurrentConfig``,
``WaveConfig``, ``PayloadEvent``, ``TetherConfig``, ...), field by field as
the struct's description in C++ lists them (its ``FIELDS``): their defaults
and their validators are the C++ ones. The C++ messages name a struct's
field (``hs``); here each section is validated on its own, so that the
message can name the TOML key (``waves.hs``) without guessing which section
a field belongs to. One reader serves every part: a new part's table is read
as soon as its header names it (``kTable``).
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

import numpy as np

from neurov import _core
from neurov.schema import field_names
from neurov.config.toml_table import TableReader, fill, read_struct, tables, validated
from neurov.errors import ScenarioError

if TYPE_CHECKING:
    from neurov.config.scenario import Scenario

__all__ = ["CURRENT_MODELS", "fill", "read_current_model", "read_part", "read_payload", "read_sea", "read_tether",
           "read_waves", "check_payload"]

CURRENT_MODELS = tuple(_core.CurrentModel.__members__)
# [current] keys of the constant model, refused with gauss_markov (the C++
# validator refuses a non-zero constant current beside it).
_CONSTANT_KEYS = ("velocity", "amplitude", "period")
# The disturbance parts' tables: key -> (bound struct, an array of tables).
_TABLES: dict[str, tuple[Any, bool]] = {key: (cls, many) for key, cls, many in _core.DISTURBANCE_TABLES}


def _probe() -> Any:
    """A configuration valid in everything but the section put into it."""
    c = _core.SimulationConfig()
    c.command = _core.Command(times=[0.0], poses=np.zeros((1, 6)))
    return c


def _validate_section(probe: Any, origin: str, prefix: str, kind: Any, lists: tuple[str, ...] = ()) -> None:
    keys = {name: f"{prefix}.{name}" for name in field_names(kind())}
    keys[prefix] = prefix
    validated(probe, origin, keys, lists)


def read_current_model(cr: TableReader, config: Any) -> bool:
    """Reads ``[current] model`` and, for ``"gauss_markov"``, its keys into
    ``config.gauss_markov_current``; True if the constant model's keys are
    still to be read."""
    model = cr.string("model", config.current_model.name, choices=CURRENT_MODELS)
    config.current_model = _core.CurrentModel.__members__[model]
    if config.current_model == _core.CurrentModel.constant:
        for key in field_names(config.gauss_markov_current):
            if key in cr.table:
                raise cr.error(key, "is a key of model = \"gauss_markov\"; this [current] table has "
                                    "model = \"constant\" (the default)")
        return True
    for key in _CONSTANT_KEYS:
        if key in cr.table:
            raise cr.error(key, "is a key of model = \"constant\"; with model = \"gauss_markov\" the "
                                "current is the Gauss-Markov process alone (speed, direction, ...)")
    gm = _core.GaussMarkovCurrentConfig()
    fill(cr, gm)
    probe = _probe()
    probe.current_model = config.current_model
    probe.gauss_markov_current = gm
    _validate_section(probe, cr.origin, cr.where, _core.GaussMarkovCurrentConfig)
    config.gauss_markov_current = gm
    return False


def read_sea(r: TableReader, config: Any) -> None:
    """The tables of the disturbance parts beside ``[current]``, in the order
    of the parts in C++ (``DisturbanceParts``, config.hpp)."""
    for key in _TABLES:
        read_part(r, config, key)


def read_part(r: TableReader, config: Any, key: str) -> None:
    """The table of one disturbance part: ``[key]`` (absent: the part is
    off; present, even empty: the C++ defaults for the keys it does not
    give) or ``[[key]]`` (the list, in its order); each table's keys under
    the struct's own field names, checked by the C++ validator."""
    kind, many = _TABLES[key]
    if many:
        value: Any = [read_struct(tr, kind) for tr in tables(r, key)]
        if not value:
            return
    else:
        if not r.has(key):
            return
        value = read_struct(r.table_of(key), kind)
    probe = _probe()
    probe.eta0 = config.eta0
    setattr(probe, key, value)
    _validate_section(probe, r.origin, key, kind, lists=(key,) if many else ())
    setattr(config, key, value)


def read_waves(r: TableReader, config: Any) -> None:
    """``[waves]``: absent, a calm sea; present (even empty), the C++
    defaults (JONSWAP, Hs 2 m, Tp 8 s) for the keys it does not give."""
    read_part(r, config, "waves")


def read_tether(r: TableReader, config: Any) -> None:
    """``[tether]``: absent, no tether; present, its keys on the C++
    defaults (``diameter`` has none that passes: it must be given)."""
    read_part(r, config, "tether")


def read_payload(r: TableReader, config: Any) -> None:
    """``[[payload]]``: the events in time order; each against the vehicle it
    changes is checked by :func:`check_payload`."""
    read_part(r, config, "payload")


def check_payload(scenario: Scenario, origin: str) -> None:
    """The payload events against the scenario's vehicle (a mass that would
    leave the vehicle with mass <= 0, a buoyancy < 0, ...), by the C++
    simulator's own check; also the one current at a time rule."""
    c = scenario.simulation
    if c.current_model == _core.CurrentModel.gauss_markov and len(c.current_steps):
        raise ScenarioError(f"{origin}: current_steps: expected none with current.model = \"gauss_markov\" "
                            "(the Gauss-Markov process is the whole current)")
    if not len(c.payload):
        return
    vehicle = scenario.vehicle_data().vehicle(scenario.vehicle_parameters)
    probe = _probe()
    probe.payload = list(c.payload)

    class _Creation:
        """The simulator's creation as a validator (it checks the events
        against the vehicle each one changes)."""

        def validate(self) -> None:
            _core.Simulator(vehicle, probe)

    validated(_Creation(), origin, {"payload": "payload"}, ("payload",))

