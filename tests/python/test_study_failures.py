"""A study survives its worst run: a run that raises, calls sys.exit or kills
its worker is a failed result and the others finish (local processes and
Dask); SIGINT and SIGTERM stop a study with a hung run within seconds and
leave no process behind."""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

from neurov.study import LOG_NAME, load_study, read_table, run_study
from neurov.study.processes import GRACE_SECONDS
from process_groups import group_members as _group_members
from study_files import MASS_PERTURBATION, pd_study, step_scenario


STUDY = pd_study("hostile", seed=5, samples=2, after=1.0) + MASS_PERTURBATION

BAD = {
    "tensor": "tensor_raises",     # its output's __array__ raises RuntimeError
    "exits": "exits",              # sys.exit(3) in a step
    "crashes": "segfaults_on_b",   # SIGSEGV in its worker, on scenario b
    "late": "fails_in_workers",    # its factory builds where the study loads, raises in a worker
}


def write(folder: Path, controllers: dict[str, str], samples: int = 2) -> Path:
    for name, x in (("a", 1), ("b", -1)):
        (folder / f"{name}.toml").write_text(step_scenario(
            name, "nerov", [0, 0, 0, 0, 0, 0], [x, 0, 1, 0, 0, 0.3], kp=50.0, kd=200.0, duration=3.0))
    text = STUDY + "".join(f'\n[controllers.{k}]\nfactory = "user_controllers.factories:{f}"\n'
                           for k, f in controllers.items())
    path = folder / "study.toml"
    path.write_text(text.replace("samples = 2", f"samples = {samples}"))
    return path


pytestmark = pytest.mark.usefixtures("user_controllers_importable")


@pytest.mark.parametrize("executor", ["processes", "dask"])
def test_failed_runs_are_results_and_the_others_finish(tmp_path: Path, executor: str) -> None:
    if executor == "dask":
        pytest.importorskip("dask.distributed")
    path = write(tmp_path, BAD, samples=1)
    out = tmp_path / executor
    outcome = run_study(path, out, executor=executor, workers=2, progress=False, plots=executor == "processes",
                        batch_size=2, **({"dask_processes": True} if executor == "dask" else {}))
    assert outcome.total == outcome.ran == 2 * 5 and outcome.without_result == 7
    table = read_table(outcome.table_path)
    assert len(table) == 10 and list(table.columns[-2:]) == ["error_kind", "error"]
    by = {c: g for c, g in table.groupby("controller")}
    ok = table[table.error_kind.isna()]
    assert set(ok.controller) == {"pd", "crashes"} and (ok.failed == 0).all() and len(ok) == 3
    assert (by["crashes"].scenario[by["crashes"].error_kind.isna()] == "a").all()
    assert (by["tensor"].error_kind == "error").all()
    # Its every step refused (as Simulator.step refuses non-numbers): in a study, a failed run.
    assert by["tensor"].error.str.startswith("ControllerError: controller 'tensor': 16 of 16 steps refused").all()
    assert by["tensor"].error.str.contains("cannot convert a tensor on a lost device").all()
    assert (by["exits"].error == "SystemExit: sys.exit(3) in the run").all()
    crashed = by["crashes"][by["crashes"].scenario == "b"]
    assert (crashed.error_kind == "crash").all() and len(crashed) == 1
    assert crashed.error.str.contains("died in this run.*again when the run was retried alone").all()
    if executor == "processes":
        assert crashed.error.str.contains("killed by SIGSEGV").all()
    assert by["late"].error.str.contains("OSError for scenario '[ab]': weights for [ab] not found").all()
    bad = table[table.error_kind.notna()]
    assert (bad.failed == 1).all() and bad.noise_seed.notna().all() and bad.p_mass.notna().all()
    # The tables count the failures by kind.
    summary = read_table(outcome.summary_path).set_index(["scenario", "controller"])
    assert summary.loc[("b", "crashes"), "failed_error"] == 1 and summary.loc[("a", "crashes"), "failed_error"] == 0
    assert summary.loc[("a", "tensor"), "failure_rate"] == 1.0
    assert (summary["failed_diverged"] == 0).all()
    league = outcome.league.read_text()
    assert "| failure rate | errors | diverged |" in league and "## Runs without a result" in league
    assert "| b | crashes | 0 | crash |" in league
    # The log has each failure with its key and error, and the study's fingerprint.
    records = [json.loads(line) for line in (out / LOG_NAME).read_text().splitlines()]
    assert {r["study"] for r in records} == {load_study(path).fingerprint()}
    crash = next(r for r in records if r["key"] == ["b", "crashes", 0])
    assert crash["error"]["kind"] == "crash" and crash["series"] is None
    # A failed run is a result: a rerun redoes nothing.
    again = run_study(path, out, executor=executor, workers=2, progress=False, plots=executor == "processes")
    assert again.ran == 0 and again.table_path.read_bytes() == outcome.table_path.read_bytes()


def test_a_study_whose_runs_all_ran_keeps_its_columns(tmp_path: Path) -> None:
    out = run_study(write(tmp_path, {}), tmp_path / "out", executor="processes", workers=1, progress=False,
                    plots=False)
    assert "error" not in out.table and "error_kind" not in out.table
    assert list(out.table.columns[:5]) == ["scenario", "vehicle", "controller", "sample", "failed"]


@pytest.mark.skipif(not Path("/proc/self/stat").exists(), reason="reads /proc")
@pytest.mark.parametrize(("executor", "signum"), [("processes", signal.SIGINT), ("processes", signal.SIGTERM),
                                                  ("dask", signal.SIGINT), ("dask", signal.SIGTERM)])
def test_a_signal_stops_a_study_with_a_hung_run_and_leaves_nothing(tmp_path: Path, executor: str,
                                                                   signum: int) -> None:
    if executor == "dask":
        pytest.importorskip("dask.distributed")
    path = write(tmp_path, {"hangs": "hangs_on_b"})
    out = tmp_path / "out"
    hung = tmp_path / "hung"
    hung.mkdir()
    proc = subprocess.Popen([sys.executable, "-m", "neurov.cli", "study", str(path), "--out", str(out),
                             "--workers", "2", "--executor", executor, "--no-plots", "--batch-size", "1"],
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, start_new_session=True,
                            env={**os.environ, "NEUROV_TEST_HANG_DIR": str(hung)})
    try:
        log = out / LOG_NAME
        deadline = time.monotonic() + 120
        # Both workers hang, each in one of scenario b's two "hangs" runs.
        while time.monotonic() < deadline and proc.poll() is None and len(list(hung.iterdir())) < 2:
            time.sleep(0.05)
        assert proc.poll() is None, proc.communicate()
        time.sleep(0.2)
        sent = time.monotonic()
        if signum == signal.SIGINT:
            os.killpg(proc.pid, signal.SIGINT)  # as a terminal's Ctrl-C: the whole group
        else:
            os.kill(proc.pid, signal.SIGTERM)  # as `kill PID`: the study's process alone
        _, err = proc.communicate(timeout=60)
        took = time.monotonic() - sent
    finally:
        if proc.poll() is None:
            os.killpg(proc.pid, signal.SIGKILL)
    # The figures docs/reliability.md quotes (pytest -s shows them).
    print(f"{executor}, {signal.Signals(signum).name}: exit {proc.returncode} {took:.2f} s after the signal")
    assert proc.returncode == 128 + signum, err
    assert took < GRACE_SECONDS + 8, took
    assert "Traceback" not in err, err
    assert err.count("\n") == 1, err
    assert f"{len(log.read_bytes().splitlines())} of 8 runs are saved in {log}" in err
    left = _group_members(proc.pid)
    for _ in range(20):  # what the kernel still reaps
        if not left:
            break
        time.sleep(0.1)
        left = _group_members(proc.pid)
    assert not left, [Path(f"/proc/{p}/cmdline").read_bytes() for p in left]
