"""Factories of the study tests: functions of the scenario returning a controller."""

from __future__ import annotations

import multiprocessing
import os
import signal
import sys
import threading
import time
from typing import Any

import numpy as np

import neurov

KP = [200.0, 200, 200, 50, 50, 50]
KD = [200.0, 200, 200, 50, 50, 50]


class Delegate:
    """A Python controller that hands every step to a built-in one."""

    def __init__(self, inner: Any) -> None:
        self.inner = inner

    def step(self, eta: Any, nu: Any, eta_d: Any, eta_d_dot: Any, eta_d_ddot: Any) -> Any:
        return self.inner.step(eta, nu, eta_d, eta_d_dot, eta_d_ddot)

    def reset(self) -> None:
        self.inner.reset()

    @property
    def s(self) -> Any:
        return self.inner.s


class PythonPD(Delegate):
    """The built-in PD law stepped from Python (a controller that is only Python glue)."""

    def __init__(self) -> None:
        super().__init__(neurov.PDController(np.array(KP), np.array(KD)))


def python_pd(scenario: neurov.Scenario) -> PythonPD:
    return PythonPD()


def not_a_controller(scenario: neurov.Scenario) -> int:
    return 42


def raises(scenario: neurov.Scenario) -> PythonPD:
    raise RuntimeError(f"no gains for {scenario.name}")


NOT_CALLABLE = 3


def tunable_pd(scenario: neurov.Scenario, gain: float = 1.0) -> Delegate:
    """The built-in PD law with both gains scaled by `gain`: a factory whose keyword argument a tuning searches."""
    return Delegate(neurov.PDController(np.array(KP) * gain, np.array(KD) * gain))


# --- controllers that fail in a run (tests/python/test_study_failures.py) ------------------
# A study calls each factory once per scenario when it loads, in its own
# process: these fail only when stepped, or only in a worker.


class _BadTensor:
    """What a tensor library hands back when its conversion to numbers fails."""

    def __array__(self, *args: Any, **kwargs: Any) -> Any:
        raise RuntimeError("cannot convert a tensor on a lost device to numbers")


class _Stepping(PythonPD):
    def __init__(self, scenario: neurov.Scenario, misbehave: Any) -> None:
        super().__init__()
        self.scenario, self.misbehave = scenario.name, misbehave

    def step(self, eta: Any, nu: Any, eta_d: Any, eta_d_dot: Any, eta_d_ddot: Any) -> Any:
        out = self.misbehave(self.scenario)
        return super().step(eta, nu, eta_d, eta_d_dot, eta_d_ddot) if out is None else out


def tensor_raises(scenario: neurov.Scenario) -> PythonPD:
    return _Stepping(scenario, lambda name: _BadTensor())


def exits(scenario: neurov.Scenario) -> PythonPD:
    def leave(name: str) -> None:
        sys.exit(3)

    return _Stepping(scenario, leave)


def segfaults_on_b(scenario: neurov.Scenario) -> PythonPD:
    """Kills its process as a crashing C extension does, on scenario b only."""
    def crash(name: str) -> None:
        if name == "b":
            os.kill(os.getpid(), signal.SIGSEGV)

    return _Stepping(scenario, crash)


def fails_in_workers(scenario: neurov.Scenario) -> PythonPD:
    """Builds in the study's own process (where the study file is checked)
    and raises in a worker, as a factory missing a file on a worker would."""
    if multiprocessing.parent_process() is not None or threading.current_thread() is not threading.main_thread():
        raise OSError(f"weights for {scenario.name} not found on this worker")
    return PythonPD()


def hangs_on_b(scenario: neurov.Scenario) -> PythonPD:
    """Never returns on scenario b, deaf to SIGTERM where it can be; leaves
    a file in $NEUROV_TEST_HANG_DIR when it starts hanging."""
    def hang(name: str) -> None:
        if name == "b":
            if threading.current_thread() is threading.main_thread():
                signal.signal(signal.SIGTERM, signal.SIG_IGN)
            folder = os.environ.get("NEUROV_TEST_HANG_DIR")
            if folder:
                open(os.path.join(folder, f"{os.getpid()}-{threading.get_ident()}"), "w").close()
            while True:
                time.sleep(1.0)

    return _Stepping(scenario, hang)
