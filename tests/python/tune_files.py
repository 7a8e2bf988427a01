"""A tiny tuning (a PD on a short surge step, one plant per trial) for the
tests that run ``neurov tune`` as a command: a trial takes a fraction of a
second, so a test of signals, resumes and broken storages takes seconds."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

from study_files import step_scenario

# A PD holding a BlueROV2 at its start, then a 1 m surge step from t = 2 s, for 3 s.
SCENARIO = step_scenario("short_step", "bluerov2_heavy", [0, 0, 1, 0, 0, 0], [1, 0, 1, 0, 0, 0.5], kp=10.0,
                         kd=10.0, duration=3.0)

TUNING = """
name = "tiny"
seed = 3
after = 0.5
scenarios = ["short_step.toml"]
[failure]
rmse_position_m = FAIL_AT
[controllers.pd]
type = "pd"
kp = [20, 20, 20, 2, 2, 2]
kd = [25, 25, 40, 1, 1, 1]
[controllers.pd.search]
kp = { scale = [SCALE_LOW, 20.0], log = true }
[tune]
trials = TRIALS
objective = "rmse_position_m"
train_samples = 1
test_samples = 1
sampler = "random"
seed = 1
"""


HANGING = """[controllers.pd]
factory = "user_controllers.factories:hangs_from_third_run"
[controllers.pd.arguments]
gain = 1.0
[controllers.pd.search]
gain = { range = [0.01, 0.15], log = true }
"""

HERE = Path(__file__).resolve().parent


def write_tiny(folder: Path, trials: int = 6, *, fail_at: float = 2.0, scale_low: float = 0.05,
               hanging: bool = False) -> Path:
    """The tuning file (and its scenario) in `folder`. `hanging`: the
    controller is a factory whose third run hangs while $NEUROV_TEST_HANG_DIR
    is set (:func:`user_controllers.factories.hangs_from_third_run`)."""
    (folder / "short_step.toml").write_text(SCENARIO)
    path = folder / "tiny.toml"
    text = TUNING.replace("TRIALS", str(trials)).replace("FAIL_AT", repr(fail_at)).replace(
        "SCALE_LOW", repr(scale_low))
    if hanging:
        head, _, rest = text.partition("[controllers.pd]")
        text = head + HANGING + rest[rest.index("[tune]"):]
    path.write_text(text)
    return path


def environment(**extra: str) -> dict[str, str]:
    """This environment, with the tests' factories importable (in spawned workers too)."""
    paths = [str(HERE), *filter(None, os.environ.get("PYTHONPATH", "").split(os.pathsep))]
    return {**os.environ, "PYTHONPATH": os.pathsep.join(paths), **extra}


def tune_command(path: Path, out: Path, *extra: str) -> list[str]:
    return [sys.executable, "-m", "neurov", "tune", str(path), "--out", str(out), "--quiet", *extra]


def run_tune(path: Path, out: Path, *extra: str, env: dict[str, str] | None = None,
             timeout: float = 180) -> subprocess.CompletedProcess[str]:
    return subprocess.run(tune_command(path, out, *extra), capture_output=True, text=True, timeout=timeout,
                          env=environment(**(env or {})))
