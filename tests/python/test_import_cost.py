"""``import neurov`` stays cheap (docs/architecture.md, "Import rules"): at
most 40 MB resident, and none of the heavy libraries that only some commands
need (Matplotlib, scipy.stats, pandas; the optional bridges' python-control,
Gymnasium, Optuna, mcap) loaded by it. Each check runs in a fresh
interpreter, so what other tests imported does not count."""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

import pytest

import neurov

MAX_RSS_MB = 40.0
HEAVY = ("matplotlib", "scipy.stats", "pandas", "control", "gymnasium", "optuna", "mcap", "plotly")

# The peak resident size of this process image: VmHWM (Linux) starts afresh
# at exec, where ru_maxrss keeps the peak of the pytest process it was forked from.
PROBE = """
import json, resource, sys
{statement}
try:
    with open("/proc/self/status") as f:
        rss_mb = next(int(line.split()[1]) for line in f if line.startswith("VmHWM:")) / 1024
except OSError:
    rss_mb = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024
print(json.dumps({{"rss_mb": rss_mb, "heavy": [m for m in {heavy!r} if m in sys.modules]}}))
"""


def _cost(statement: str) -> dict:
    # The neurov this test process imported (installed, or a source tree on
    # PYTHONPATH), whatever the fresh interpreter's working folder.
    home = str(Path(neurov.__file__).resolve().parents[1])
    env = {**os.environ, "PYTHONPATH": os.pathsep.join([home, os.environ.get("PYTHONPATH", "")])}
    out = subprocess.run([sys.executable, "-c", PROBE.format(statement=statement, heavy=HEAVY)],
                         capture_output=True, text=True, env=env, check=True, timeout=120)
    return json.loads(out.stdout.strip().splitlines()[-1])


@pytest.mark.parametrize("statement", ["import neurov", "import neurov.running.simulation",
                                       "import neurov.config.reading", "import neurov.results.load"])
def test_import_neurov_is_cheap(statement: str) -> None:
    cost = _cost(statement)
    assert cost["heavy"] == [], f"{statement} loads {cost['heavy']}"
    assert cost["rss_mb"] <= MAX_RSS_MB, f"{statement}: {cost['rss_mb']:.1f} MB resident"


def test_the_probe_sees_a_heavy_import() -> None:
    """The check above can fail: importing pandas is seen."""
    assert "pandas" in _cost("import neurov, pandas")["heavy"]
