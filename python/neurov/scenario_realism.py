"""The scenario keys of the vehicle as it really is (the timing, the water,
the sensors and the estimator), read into the core's ``SimulationConfig``.

Called by :mod:`neurov.scenario_file` with its reader; the rules (a delay of
0..16 whole periods, a density > 0, ...) are the C++ validators', whose
messages come back naming the TOML key."""

from __future__ import annotations

from typing import Any

__all__ = ["REALISM_KEYS", "read_realism"]

# SimulationConfig field -> TOML key, for the validator's messages.
REALISM_KEYS: dict[str, str] = {}


def read_realism(r: Any, c: Any) -> None:
    """Reads the top-level keys of reader `r` into config `c`."""
    # Any integer reaches the C++ validator, which names the allowed range.
    c.control_delay = r.integer("control_delay", c.control_delay, minimum=-(2**31))
    c.water_density = r.number("water_density", c.water_density)
