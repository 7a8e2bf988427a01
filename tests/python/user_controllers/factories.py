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


# --- batched policies (tests/python/test_study_batched.py) ---------------------------------


def _numpy_pd(eta: Any, nu: Any, eta_d: Any) -> Any:
    """A PD law in numpy on rows (K, 6) or one row (6,): earth-frame pose error, body velocity."""
    return -np.array(KP) * 0.01 * (eta - eta_d) - np.array(KD) * 0.01 * nu


class NumpyPD:
    """The numpy law, run by run."""

    def step(self, eta: Any, nu: Any, eta_d: Any, eta_d_dot: Any, eta_d_ddot: Any) -> Any:
        return _numpy_pd(eta, nu, eta_d)


class BatchedNumpyPD:
    """The same law on K runs per call."""

    batched = True

    def step_batch(self, eta: Any, nu: Any, eta_d: Any, eta_d_dot: Any, eta_d_ddot: Any) -> Any:
        return _numpy_pd(eta, nu, eta_d)


class FailsOnSecondRunAlone(BatchedNumpyPD):
    """Raises on any batch of more than one run, and on the second run it is
    given alone: in a study's batch of three, only that run may fail."""

    def __init__(self) -> None:
        self.resets = 0

    def reset(self) -> None:
        self.resets += 1

    def step_batch(self, eta: Any, nu: Any, eta_d: Any, eta_d_dot: Any, eta_d_ddot: Any) -> Any:
        if len(eta) > 1 or self.resets == 3:  # reset 1: the batch; 2, 3, 4: the runs alone
            raise RuntimeError("this policy fails")
        return _numpy_pd(eta, nu, eta_d)


def numpy_pd(scenario: neurov.Scenario) -> NumpyPD:
    return NumpyPD()


def batched_numpy_pd(scenario: neurov.Scenario) -> BatchedNumpyPD:
    return BatchedNumpyPD()


def fails_on_second_run_alone(scenario: neurov.Scenario) -> FailsOnSecondRunAlone:
    return FailsOnSecondRunAlone()


# --- factories that count their calls (tests/python/test_study_batched.py) -----------------


def _count_call(scenario: neurov.Scenario) -> None:
    """A line "pid scenario" in $NEUROV_TEST_CALLS_FILE per call of a counted factory."""
    path = os.environ.get("NEUROV_TEST_CALLS_FILE")
    if path:
        with open(path, "a") as f:
            f.write(f"{os.getpid()} {scenario.name}\n")


def counted_numpy_pd(scenario: neurov.Scenario) -> NumpyPD:
    _count_call(scenario)
    return NumpyPD()


def counted_batched_numpy_pd(scenario: neurov.Scenario) -> BatchedNumpyPD:
    _count_call(scenario)
    return BatchedNumpyPD()


# --- a tuned controller that hangs (tests/python/test_tune_signals.py) ---------------------


class _HangsFromThirdRun(Delegate):
    def __init__(self, inner: Any) -> None:
        super().__init__(inner)
        self.started = False

    def step(self, *args: Any) -> Any:  # type: ignore[override]
        folder = os.environ.get("NEUROV_TEST_HANG_DIR")
        if folder and not self.started:
            self.started = True
            open(os.path.join(folder, f"{os.getpid()}-{time.monotonic_ns()}"), "w").close()
            if len(os.listdir(folder)) >= 3:
                if threading.current_thread() is threading.main_thread():
                    signal.signal(signal.SIGTERM, signal.SIG_IGN)
                while True:
                    time.sleep(1.0)
        return self.inner.step(*args)

    def reset(self) -> None:
        self.started = False
        self.inner.reset()


def hangs_from_third_run(scenario: neurov.Scenario, gain: float = 1.0) -> Delegate:
    """:func:`tunable_pd`, whose runs each leave a file in
    $NEUROV_TEST_HANG_DIR when they start; from the third on (the third trial
    of a one-run-per-trial tuning) the run hangs, deaf to SIGTERM where it
    can be. Without the variable it is :func:`tunable_pd`."""
    return _HangsFromThirdRun(neurov.PDController(np.array(KP) * gain, np.array(KD) * gain))
