"""``neurov tune`` stopped by Ctrl-C, SIGTERM or SIGKILL, on the real
command: nothing of it outlives it (its worker processes and the
multiprocessing resource tracker included), it says in one line what is
saved and exits 130 or 143, and the storage stays consistent."""

from __future__ import annotations

import contextlib
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

pytest.importorskip("optuna")

from process_groups import group_members  # noqa: E402
from tune_files import environment, run_tune, tune_command, write_tiny  # noqa: E402

pytestmark = pytest.mark.skipif(sys.platform != "linux", reason="process groups and /proc are read on Linux")


def left_after(pgid: int, seconds: float = 3.0) -> list[str]:
    """The group's processes still there `seconds` after its leader ended."""
    deadline = time.monotonic() + seconds
    while True:
        left = group_members(pgid)
        if not left or time.monotonic() > deadline:
            break
        time.sleep(0.1)
    names = []
    for p in left:
        try:
            names.append(Path(f"/proc/{p}/cmdline").read_bytes().replace(b"\0", b" ").decode()[:200])
        except OSError:
            pass
    return names


def start_hanging(tmp_path: Path, workers: int = 2) -> tuple[subprocess.Popen[str], Path]:
    """A tuning whose third trial hangs in a worker process; returns once it hangs."""
    path = write_tiny(tmp_path, trials=6, hanging=True)
    hung = tmp_path / "hung"
    hung.mkdir()
    proc = subprocess.Popen(tune_command(path, tmp_path / "out", "--workers", str(workers), "--no-verdict"),
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, start_new_session=True,
                            env=environment(NEUROV_TEST_HANG_DIR=str(hung)))
    deadline = time.monotonic() + 120
    while time.monotonic() < deadline and proc.poll() is None and len(list(hung.iterdir())) < 3:
        time.sleep(0.05)
    assert proc.poll() is None, proc.communicate()
    time.sleep(0.3)
    return proc, path


def stop(proc: subprocess.Popen[str], signum: int, group: bool) -> tuple[str, float, list[str]]:
    """Sends `signum`; returns the tuning's stderr, the seconds until it ended
    and what is left of its process group after it."""
    sent = time.monotonic()
    try:
        if group:
            os.killpg(proc.pid, signum)  # a terminal's Ctrl-C: the whole group
        else:
            os.kill(proc.pid, signum)  # `kill PID`, a job scheduler, the OOM killer: the process alone
        _, err = proc.communicate(timeout=30)
    except subprocess.TimeoutExpired:
        err = "the tuning or one of its processes did not end within 30 s"
    took = time.monotonic() - sent
    left = left_after(proc.pid)
    with contextlib.suppress(ProcessLookupError):  # whatever is left, once looked at
        os.killpg(proc.pid, signal.SIGKILL)
    proc.communicate()
    return err, took, left


def finished_trials(path: Path, out: Path) -> list[int]:
    import optuna

    from neurov.tuning import load_tuning
    from neurov.tuning.search import open_storage, optuna_study

    study = optuna_study(load_tuning(path), "pd", open_storage(out))
    return [t.number for t in study.trials if t.state == optuna.trial.TrialState.COMPLETE]


@pytest.mark.parametrize(("signum", "group"), [(signal.SIGINT, True), (signal.SIGTERM, False)],
                         ids=["ctrl-c", "sigterm"])
def test_a_signal_stops_a_tuning_with_a_hung_trial_and_leaves_nothing(tmp_path: Path, signum: int,
                                                                       group: bool) -> None:
    proc, path = start_hanging(tmp_path)
    err, took, leftover = stop(proc, signum, group)
    # The figures docs/reliability.md quotes (pytest -s shows them).
    print(f"{signal.Signals(signum).name}: exit {proc.returncode} {took:.2f} s after the signal")
    assert not leftover, leftover
    assert proc.returncode == 128 + signum, err
    assert "Traceback" not in err and err.count("\n") == 1, err
    assert f"2 of 6 trials are saved in {tmp_path / 'out' / 'tuning.db'}" in err, err
    assert took < 15, took
    # The resume runs the interrupted trial again and ends with the budget.
    again = run_tune(path, tmp_path / "out", "--workers", "2", "--no-verdict")
    assert again.returncode == 0, again.stderr
    assert "4 run now" in again.stdout, again.stdout
    assert len(finished_trials(path, tmp_path / "out")) == 6


def test_sigkill_of_a_tuning_leaves_no_process_and_the_resume_ends_with_the_budget(tmp_path: Path) -> None:
    proc, path = start_hanging(tmp_path)
    err, _, leftover = stop(proc, signal.SIGKILL, group=False)
    assert not leftover, leftover
    assert proc.returncode == -signal.SIGKILL
    # Its trial is left "running" in the storage, its process dead: the resume
    # (within Optuna's 60 s grace) fails it and runs it again.
    again = run_tune(path, tmp_path / "out", "--workers", "2", "--no-verdict")
    assert again.returncode == 0, again.stderr
    assert "4 run now" in again.stdout, again.stdout
    assert len(finished_trials(path, tmp_path / "out")) == 6
