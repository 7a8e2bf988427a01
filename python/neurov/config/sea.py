"""Reading the sea of a scenario file: ``[current] model = "gauss_markov"``,
``[waves]``, ``[[payload]]`` and ``[tether]`` (docs/disturbances.md).

Each value goes into the core's own struct (``GaussMarkovCurrentConfig``,
``WaveConfig``, ``PayloadEvent``, ``TetherConfig``): their defaults and their validators are
the C++ ones. The C++ messages name a struct's field (``hs``); here each
section is validated on its own, so that the message can name the TOML key
(``waves.hs``) without guessing which section a field belongs to.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

import numpy as np

from neurov import _core
from neurov.schema import SchemaError, convert, field_names
from neurov.config.toml_table import TableReader, tables, validated
from neurov.errors import ScenarioError

if TYPE_CHECKING:
    from neurov.config.scenario import Scenario

__all__ = ["CURRENT_MODELS", "read_current_model", "read_payload", "read_sea", "read_tether", "read_waves",
           "check_payload"]

CURRENT_MODELS = tuple(_core.CurrentModel.__members__)
# [current] keys of the constant model, refused with gauss_markov (the C++
# validator refuses a non-zero constant current beside it).
_CONSTANT_KEYS = ("velocity", "amplitude", "period")
# PayloadEvent fields that may be left empty (None: the vehicle's own point).
_OPTIONAL_POINTS = ("mass_position", "buoyancy_position")


def _fill(r: TableReader, target: Any, skip: tuple[str, ...] = ()) -> None:
    """Every field of the bound struct `target` that the table gives, under
    the field's own name, converted by the kind of the field's default."""
    for key in field_names(target):
        if key in skip or not r.has(key):
            continue
        try:
            setattr(target, key, convert(getattr(target, key), r.raw(key), r._name(key)))
        except SchemaError as e:
            raise ScenarioError(f"{r.origin}: {e}") from None


def _probe() -> Any:
    """A configuration valid in everything but the section put into it."""
    c = _core.SimulationConfig()
    c.command = _core.Command(times=[0.0], poses=np.zeros((1, 6)))
    return c


def _validate_section(probe: Any, origin: str, prefix: str, lists: tuple[str, ...] = ()) -> None:
    keys = {name: f"{prefix}.{name}" for name in
            (*field_names(_core.GaussMarkovCurrentConfig()), *field_names(_core.WaveConfig()))}
    keys["payload"] = "payload"
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
    _fill(cr, gm)
    probe = _probe()
    probe.current_model = config.current_model
    probe.gauss_markov_current = gm
    _validate_section(probe, cr.origin, cr.where)
    config.gauss_markov_current = gm
    return False


def read_sea(r: TableReader, config: Any) -> None:
    """The tables of the disturbance parts beside ``[current]``: each one's
    reader, in the order of the parts in C++ (config.hpp)."""
    read_waves(r, config)
    read_payload(r, config)
    read_tether(r, config)


def read_waves(r: TableReader, config: Any) -> None:
    """``[waves]``: absent, a calm sea; present (even empty), the C++
    defaults (JONSWAP, Hs 2 m, Tp 8 s) for the keys it does not give."""
    if not r.has("waves"):
        return
    wr = r.table_of("waves")
    # Checked here too: a count beyond a C++ int would not reach the validator.
    wr.integer("components", 0, minimum=-(2**31),
               maximum=(_core.MAX_WAVE_COMPONENTS, "the wave field's capacity, neurov.MAX_WAVE_COMPONENTS"))
    waves = _core.WaveConfig()
    _fill(wr, waves)
    wr.finish()
    probe = _probe()
    probe.waves = waves
    _validate_section(probe, r.origin, "waves")
    config.waves = waves


def read_tether(r: TableReader, config: Any) -> None:
    """``[tether]``: absent, no tether; present, its keys on the C++
    defaults (``diameter`` has none that passes: it must be given)."""
    if not r.has("tether"):
        return
    tr = r.table_of("tether")
    tether = _core.TetherConfig()
    _fill(tr, tether)
    tr.finish()
    probe = _probe()
    probe.eta0 = config.eta0
    probe.tether = tether
    _validate_section(probe, r.origin, "tether")
    config.tether = tether


def read_payload(r: TableReader, config: Any) -> None:
    """``[[payload]]``: the events in time order; each against the vehicle it
    changes is checked by :func:`check_payload`."""
    events = []
    for pr in tables(r, "payload"):
        event = _core.PayloadEvent()
        for key in _OPTIONAL_POINTS:
            if pr.has(key):
                setattr(event, key, pr.array(key, 3, broadcast=False))
        _fill(pr, event, skip=_OPTIONAL_POINTS)
        pr.finish()
        events.append(event)
    if not events:
        return
    probe = _probe()
    probe.payload = events
    _validate_section(probe, r.origin, "payload", lists=("payload",))
    config.payload = events


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

