"""The scenario keys of the vehicle as it really is (the timing, the water,
the sensors and the estimator), read into the core's ``SimulationConfig``::

    water_density = 1025.0       # kg/m^3
    control_delay = 1            # control periods between measurement and thrust
    [sensors]                    # absent: ideal sensing
    usbl = { rate = 1.0, noise = 0.5, latency = 0.5 }          # Hz, m, s
    dvl = { rate = 5.0, noise = 0.01, dropout_rate = 0.01 }    # Hz, m/s, per sample
    depth = { rate = 10.0, noise = 0.02 }
    imu = { rate = 50.0, attitude_noise = 0.005, gyro_noise = 0.001, gyro_bias_walk = 1e-5 }
    [estimator]
    type = "ekf"                 # or "none"

Called by :mod:`neurov.config.reading` with its reader; the rules (a delay of
0..16 whole periods, a rate > 0, an estimator with the sensors it needs) are
the C++ validators', whose messages name the TOML key (``sensors.usbl.rate``)."""

from __future__ import annotations

from typing import Any

from neurov import _core
from neurov.config.toml_table import read_struct

__all__ = ["REALISM_KEYS", "read_realism"]

# SimulationConfig field -> TOML key, for the validator's messages (the
# sensors' and the estimator's messages already name theirs).
REALISM_KEYS: dict[str, str] = {}

# TOML key -> the bound sensor config, whose keys are its fields (FIELDS).
_SENSORS: dict[str, Any] = {
    "usbl": _core.UsblConfig, "dvl": _core.DvlConfig, "depth": _core.DepthConfig, "imu": _core.ImuConfig,
}


def read_realism(r: Any, c: Any) -> None:
    """Reads the top-level keys of reader `r` into config `c`."""
    # Any integer reaches the C++ validator, which names the allowed range.
    c.control_delay = r.integer("control_delay", c.control_delay, minimum=-(2**31))
    c.water_density = r.number("water_density", c.water_density)
    sensors = _core.SensorsConfig()
    table = r.table_of("sensors")
    for key, kind in _SENSORS.items():
        if table.has(key):
            setattr(sensors, key, read_struct(table.table_of(key), kind))
    table.finish()
    c.sensors = sensors
    c.estimator = read_struct(r.table_of("estimator"), _core.EstimatorConfig)
