"""A stopped tuning resumes to exactly its budget: Ctrl-C at any moment
(in Optuna's own bookkeeping too) exits 130 in one line with no trial left
"running", and a trial left running by a process that died is failed and
its place run again, at once when its process is known dead and after
Optuna's grace period when only its silent heartbeat tells."""

from __future__ import annotations

import contextlib
import sqlite3
import subprocess
import sys
import warnings
from pathlib import Path

import pytest

optuna = pytest.importorskip("optuna")

from tune_files import environment, write_tiny  # noqa: E402

from neurov import cli  # noqa: E402

from neurov.tuning import load_tuning  # noqa: E402
from neurov.tuning.search import open_storage, optuna_study  # noqa: E402
from neurov.tuning.storage import GRACE_SECONDS  # noqa: E402

# Sends SIGINT to itself inside the storage call METHOD (the NTH call), as a
# Ctrl-C at that unlucky moment would, then runs `neurov tune`.
UNLUCKY = """
import os, signal, sys
import optuna
from neurov import cli

method, nth = sys.argv[1], int(sys.argv[2])
real = getattr(optuna.storages.RDBStorage, method)
calls = 0

def unlucky(self, *args, **kwargs):
    global calls
    calls += 1
    if calls == nth:
        os.kill(os.getpid(), signal.SIGINT)
    return real(self, *args, **kwargs)

setattr(optuna.storages.RDBStorage, method, unlucky)
sys.exit(cli.main(sys.argv[3:]))
"""


def resume(path: Path, out: Path) -> int:
    """The same command again (here, in this process: the stop was in another)."""
    return cli.main(["tune", str(path), "--out", str(out), "--workers", "1", "--quiet", "--no-verdict",
                     "--no-plots"])


def states(path: Path, out: Path) -> list[str]:
    study = optuna_study(load_tuning(path), "pd", open_storage(out))
    return [t.state.name for t in study.trials]


@pytest.mark.parametrize(("method", "nth"), [("set_trial_state_values", 3), ("_create_new_trial", 3),
                                             ("set_trial_intermediate_value", 2)])
def test_ctrl_c_in_optunas_bookkeeping_exits_130_and_the_resume_ends_with_the_budget(
        tmp_path: Path, method: str, nth: int) -> None:
    path = write_tiny(tmp_path, trials=6)
    text = path.read_text()
    path.write_text(text.replace('sampler = "random"', 'sampler = "random"\ntrain_samples = 2'
                                 ).replace("train_samples = 1\n", ""))  # two runs: a report between them
    out = tmp_path / "out"
    r = subprocess.run([sys.executable, "-c", UNLUCKY, method, str(nth), "tune", str(path), "--out", str(out),
                        "--workers", "1", "--quiet", "--no-verdict", "--no-plots"],
                       capture_output=True, text=True, timeout=120, env=environment())
    assert r.returncode == 130, r.stderr
    assert "Traceback" not in r.stderr and r.stderr.count("\n") == 1, r.stderr
    assert r.stderr.startswith("neurov: interrupted: "), r.stderr
    assert "RUNNING" not in states(path, out)  # the interrupted trial is marked failed, not left running
    assert resume(path, out) == 0
    assert states(path, out).count("COMPLETE") == 6


def test_a_trial_whose_heartbeat_stopped_is_run_again(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    path = write_tiny(tmp_path, trials=3)
    out = tmp_path / "out"
    assert resume(path, out) == 0
    # A trial of a process on another machine that died a while ago: running,
    # its last heartbeat longer ago than the grace period.
    storage = open_storage(out)
    study = optuna_study(load_tuning(path), "pd", storage)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", UserWarning)  # Optuna's: a heartbeat is meant for its optimize loop
        trial = study.ask()
    trial.set_user_attr("process", {"machine": "elsewhere/boot", "pid": 12345, "started": 1})
    storage.record_heartbeat(trial._trial_id)
    with contextlib.closing(sqlite3.connect(out / "tuning.db")) as c, c:
        c.execute(f"UPDATE trial_heartbeats SET heartbeat = datetime(heartbeat, '-{GRACE_SECONDS + 5} seconds')")
    del storage, study
    text = path.read_text()
    path.write_text(text.replace("trials = 3", "trials = 5"))
    assert resume(path, out) == 0
    assert "2 run now" in capsys.readouterr().out
    assert states(path, out) == ["COMPLETE"] * 3 + ["FAIL"] + ["COMPLETE"] * 2
