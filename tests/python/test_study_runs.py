"""Running studies: the same table from Dask and from local processes,
resuming, the command line, Ctrl-C, and redrawing plots only when their data
changed."""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

from neurov import cli
from neurov.study import (
    LOG_NAME,
    StudyError,
    failed,
    league_markdown,
    load_study,
    percentile,
    read_table,
    run_study,
    summarise,
)

from study_files import STUDY, study_file, study_with, write_study  # noqa: F401  (study_file: a fixture)


# --- running -------------------------------------------------------------------------


def test_dask_and_local_processes_give_identical_tables(study_file: Path, tmp_path: Path) -> None:
    pytest.importorskip("dask.distributed")
    a = run_study(study_file, tmp_path / "dask", executor="dask", workers=2, dask_processes=False,
                  progress=False, plots=False)
    b = run_study(study_file, tmp_path / "procs", executor="processes", workers=2, progress=False,
                  plots=True)
    assert a.executor == "dask" and b.executor == "processes"
    assert a.total == b.total == 2 * 3 * 4 and a.ran == b.ran == 24
    assert a.table_path.read_bytes() == b.table_path.read_bytes()
    assert a.league.read_text() == b.league.read_text()
    pd.testing.assert_frame_equal(read_table(b.table_path), b.table)
    rows = b.table.to_dict("records")
    assert len(rows) == 24
    assert [(r["scenario"], r["controller"], r["sample"]) for r in rows[:5]] == [
        ("short_nerov", "pd", 0), ("short_nerov", "pd", 1), ("short_nerov", "pd", 2),
        ("short_nerov", "pd", 3), ("short_nerov", "linear", 0)]
    assert {"rmse_position_m", "rmse_yaw", "p_mass", "p_added_mass_5", "failed", "noise_seed"} <= set(rows[0])
    assert all(math.isfinite(r["rmse_position_m"]) for r in rows)
    for name in ("boxplot_rmse_position_m.png", "error_bands_short_nerov.png", "error_bands_short_bluerov.png"):
        assert (tmp_path / "procs" / name).stat().st_size > 10_000
    timing = json.loads((tmp_path / "procs" / "timing.json").read_text())
    assert timing["runs"] == 24 and timing["runs_per_second"] > 0


def test_runs_batched_in_cpp_give_the_table_of_runs_one_by_one(study_file: Path, tmp_path: Path) -> None:
    # batch_size=1: every run alone through neurov.simulate; 24: the built-in
    # controllers' runs of a batch in one simulate_many, plants drawn once a batch.
    alone = run_study(study_file, tmp_path / "alone", executor="processes", workers=1, batch_size=1,
                      progress=False, plots=False)
    batched = run_study(study_file, tmp_path / "batched", executor="processes", workers=1, batch_size=24,
                        progress=False, plots=False)
    assert alone.ran == batched.ran == 24
    assert alone.table_path.read_bytes() == batched.table_path.read_bytes()
    series = [{tuple(json.loads(line)["key"]): json.loads(line)["series"]
               for line in (tmp_path / name / LOG_NAME).read_text().splitlines()} for name in ("alone", "batched")]
    assert series[0] == series[1]


def test_resume_skips_finished_runs_and_gives_the_same_table(study_file: Path, tmp_path: Path) -> None:
    out = tmp_path / "out"
    first = run_study(study_file, out, executor="processes", workers=1, progress=False, plots=False)
    table = first.table_path.read_bytes()
    again = run_study(study_file, out, executor="processes", workers=1, progress=False, plots=False)
    assert again.ran == 0 and again.skipped == 24
    assert again.table_path.read_bytes() == table
    # Lose five runs, and cut the last line short as an interrupted write would.
    lines = (out / LOG_NAME).read_text().splitlines(keepends=True)
    kept = lines[:18] + [lines[18][:40]]
    (out / LOG_NAME).write_text("".join(kept))
    resumed = run_study(study_file, out, executor="processes", workers=1, progress=False, plots=False)
    assert resumed.ran == 6 and resumed.skipped == 18
    assert resumed.table_path.read_bytes() == table


def test_more_samples_reuse_the_runs_already_made(tmp_path: Path) -> None:
    two = write_study(tmp_path, STUDY.replace("samples = 4", "samples = 2"), "two.toml")
    four = write_study(tmp_path, STUDY, "four.toml")
    out = tmp_path / "out"
    run_study(two, out, executor="processes", workers=1, progress=False, plots=False)
    more = run_study(four, out, executor="processes", workers=1, progress=False, plots=False)
    assert more.ran == 12 and more.skipped == 12
    fresh = run_study(four, tmp_path / "fresh", executor="processes", workers=1, progress=False, plots=False)
    assert more.table_path.read_bytes() == fresh.table_path.read_bytes()


def test_a_different_study_in_the_same_folder_is_refused(tmp_path: Path) -> None:
    out = tmp_path / "out"
    small = STUDY.replace("samples = 4", "samples = 1")
    run_study(write_study(tmp_path, small, "a.toml"), out, executor="processes", workers=1,
              progress=False, plots=False)
    other = write_study(tmp_path, small.replace("seed = 7", "seed = 8"), "b.toml")
    with pytest.raises(StudyError, match="holds runs of a different study"):
        run_study(other, out, executor="processes", workers=1, progress=False, plots=False)
    # Judging differently is not a different study: no run is redone.
    judged = write_study(tmp_path, small.replace("rmse_position_m = 0.5", "rmse_position_m = 0.01"), "c.toml")
    outcome = run_study(judged, out, executor="processes", workers=1, progress=False, plots=False)
    assert outcome.ran == 0
    table = read_table(outcome.table_path)
    assert (table.loc[table["rmse_position_m"] > 0.01, "failed"] == 1).all()


# --- summaries -------------------------------------------------------------------------


def test_percentile_handles_inf() -> None:
    assert percentile([1.0, 2.0, 3.0], 50) == 2.0
    assert percentile([1.0, 2.0, 3.0, 4.0], 5) == pytest.approx(np.percentile([1, 2, 3, 4], 5))
    assert percentile([1.0, float("nan"), float("inf")], 50) == float("inf")
    assert percentile([1.0, 2.0, float("inf")], 50) == 2.0
    assert percentile([1.0, 2.0, float("inf")], 95) == float("inf")


def test_failure_is_a_stated_bound_or_a_non_finite_value() -> None:
    row = {"rmse_position_m": 0.2, "rmse_yaw_rad": 0.1, "diverged": 0.0, "max_position_error_m": 1.0}
    assert not failed(row, {"rmse_position_m": 0.5})
    assert failed(row, {"rmse_position_m": 0.1})
    assert failed(row | {"rmse_yaw_rad": float("nan")}, {})
    assert failed(row | {"diverged": 1.0}, {})
    assert failed(row | {"max_position_error_m": float("inf")}, {"max_position_error_m": 5.0})


def test_league_table_ranks_by_the_median(study_file: Path) -> None:
    s = load_study(study_file)
    s.failure = {"rmse_position_m": 5.0}
    rows = []
    values = {"pd": [3.0, 3.0, 3.0, 3.0], "linear": [1.0, 2.0, 2.0, 9.0], "nn": [1.0, 1.0, 1.0, float("inf")]}
    for sc in s.scenarios:
        for c, vals in values.items():
            for k, v in enumerate(vals):
                rows.append({"scenario": sc.name, "controller": c, "sample": k, "rmse_position_m": v,
                             "rmse_yaw_rad": 0.0, "diverged": 0.0})
    summ = summarise(s, rows)
    first = [g for g in summ if g.scenario == "short_nerov"]
    assert [g.controller for g in first] == ["nn", "linear", "pd"]
    assert first[0].median == 1.0 and first[0].failure_rate == 0.25  # inf: not finite
    assert first[1].median == 2.0 and first[1].failure_rate == 0.25  # 9 > the bound of 5
    assert first[2].failure_rate == 0.0
    md = league_markdown(s, rows)
    assert "| 1 | NN adaptive | 1 |" in md
    s.also_show = ["rmse_yaw_rad"]
    assert "| median RMS yaw error [deg] |" in league_markdown(s, rows)  # for people: degrees (neurov.units)
    assert "## NN adaptive against linear adaptive" in md
    assert "| short_nerov | 2 of 4 |" in md  # nn < linear in samples 1 and 2 only


# --- command line ------------------------------------------------------------------------


def test_cli_study_writes_the_outputs(study_file: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    small = write_study(tmp_path, STUDY.replace("samples = 4", "samples = 1"), "one.toml")
    out = tmp_path / "cli"
    assert cli.main(["study", str(small), "--out", str(out), "--workers", "1", "--executor", "processes",
                     "--no-plots"]) == 0
    text = capsys.readouterr().out
    assert "6 runs (0 already done, 6 run in" in text
    assert "on 1 local process," in text and "worker(s)" not in text
    for name in ("runs.csv", "summary.csv", "league.md", "study.json", "timing.json", LOG_NAME):
        assert (out / name).exists()
    assert cli.main(["study", str(small), "--out", str(out), "--workers", "1", "--executor", "processes",
                     "--no-plots"]) == 0
    assert "6 already done, 0 run" in capsys.readouterr().out


def test_cli_study_error_names_the_field(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    path = write_study(tmp_path, study_with("[ranking]\nmetric = \"speed\""))
    assert cli.main(["study", str(path), "--out", str(tmp_path / "o")]) == 1
    err = capsys.readouterr().err
    assert "ranking.metric: unknown metric 'speed'" in err and str(path) in err


def test_parquet_table_reads_back_as_the_csv_rows(tmp_path: Path) -> None:
    pytest.importorskip("pyarrow")
    small = write_study(tmp_path, STUDY.replace("samples = 4", "samples = 1"), "one.toml")
    a = run_study(small, tmp_path / "csv", executor="processes", workers=1, progress=False, plots=False)
    b = run_study(small, tmp_path / "pq", executor="processes", workers=1, progress=False, plots=False,
                  table_format="parquet")
    assert b.table_path.suffix == ".parquet"
    pd.testing.assert_frame_equal(read_table(a.table_path), read_table(b.table_path))


def test_a_folder_named_like_a_shipped_study_does_not_hide_it(tmp_path: Path,
                                                               monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.chdir(tmp_path)
    (tmp_path / "league").mkdir()  # e.g. the output of `neurov study league --out league`
    assert load_study("league").name == "league"


# --- crashes, interrupts and reruns ---------------------------------------------------------


def test_a_log_cut_by_a_crash_is_repaired_before_appending(tmp_path: Path) -> None:
    small = write_study(tmp_path, STUDY.replace("samples = 4", "samples = 1"), "one.toml")
    out = tmp_path / "out"
    first = run_study(small, out, executor="processes", workers=1, progress=False, plots=False)
    log = out / LOG_NAME
    lines = log.read_text().splitlines(keepends=True)
    # The crash: the last record half written, no newline.
    log.write_text("".join(lines[:-1]) + lines[-1][:50])
    resumed = run_study(small, out, executor="processes", workers=1, progress=False, plots=False)
    assert resumed.ran == 1
    # The broken line is gone and the finished run is on a line of its own.
    after = log.read_text().splitlines()
    assert len(after) == len(lines) and all(json.loads(line)["row"] for line in after)
    again = run_study(small, out, executor="processes", workers=1, progress=False, plots=False)
    assert again.ran == 0 and again.table_path.read_bytes() == first.table_path.read_bytes()


def test_repair_tail_keeps_complete_lines(tmp_path: Path) -> None:
    from neurov.study.log import repair_tail

    log = tmp_path / "log.jsonl"
    assert repair_tail(log) == 0  # no file yet
    log.write_bytes(b'{"a": 1}\n{"b": 2}\n')
    assert repair_tail(log) == 0 and log.read_bytes() == b'{"a": 1}\n{"b": 2}\n'
    log.write_bytes(b'{"a": 1}\n{"b": 2}\n{"c": ')
    assert repair_tail(log) == 6 and log.read_bytes() == b'{"a": 1}\n{"b": 2}\n'
    log.write_bytes(b"x" * 100_000)  # one broken line, longer than a read block
    assert repair_tail(log) == 100_000 and log.read_bytes() == b""


def test_ctrl_c_says_what_is_saved_and_exits_130(tmp_path: Path, monkeypatch: pytest.MonkeyPatch,
                                                 capsys: pytest.CaptureFixture[str]) -> None:
    import neurov.study.running as running

    small = write_study(tmp_path, STUDY.replace("samples = 4", "samples = 1"), "one.toml")
    out = tmp_path / "out"
    real = running.run_batch
    calls = []

    def interrupted_on_the_third(study: object, keys: object) -> object:
        calls.append(keys)
        if len(calls) == 3:
            raise KeyboardInterrupt
        return real(study, keys)  # type: ignore[arg-type]

    monkeypatch.setattr(running, "run_batch", interrupted_on_the_third)
    args = ["study", str(small), "--out", str(out), "--workers", "1", "--executor", "processes",
            "--no-plots", "--batch-size", "1"]
    assert cli.main(args) == 130
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "Traceback" not in err
    assert f"2 of 6 runs are saved in {out / LOG_NAME}" in err and "again to resume" in err
    monkeypatch.setattr(running, "run_batch", real)
    assert cli.main(args) == 0
    assert "6 runs (2 already done, 4 run in" in capsys.readouterr().out


def test_ctrl_c_before_a_study_starts_says_interrupted(tmp_path: Path, monkeypatch: pytest.MonkeyPatch,
                                                       capsys: pytest.CaptureFixture[str]) -> None:
    import neurov.study as study

    def interrupted(*_: object, **__: object) -> object:
        raise KeyboardInterrupt  # a bare one, as Python raises it: no message of its own

    monkeypatch.setattr(study, "main_study", interrupted)
    assert cli.main(["study", str(write_study(tmp_path)), "--out", str(tmp_path / "out")]) == 130
    assert capsys.readouterr().err == "neurov: interrupted\n"


@pytest.mark.skipif(not Path("/proc/self/status").exists(), reason="reads /proc")
def test_workers_start_with_ctrl_c_ignored() -> None:
    """A spawned worker imports for a second before it runs anything; SIGINT
    must be ignored from its start, or a Ctrl-C then prints its traceback."""
    import multiprocessing
    import signal

    from neurov.study import processes

    before = signal.getsignal(signal.SIGINT)
    worker = processes._Worker(multiprocessing.get_context("spawn"), None)  # type: ignore[arg-type]
    try:
        status = Path(f"/proc/{worker.proc.pid}/status").read_text()
        ignored = int(next(x for x in status.splitlines() if x.startswith("SigIgn:")).split()[1], 16)
        assert ignored & (1 << (signal.SIGINT - 1))
    finally:
        processes._stop([worker])
    assert signal.getsignal(signal.SIGINT) is before


def test_plots_are_redrawn_only_when_their_data_changed(tmp_path: Path) -> None:
    one = write_study(tmp_path, STUDY.replace("samples = 4", "samples = 1"), "one.toml")
    two = write_study(tmp_path, STUDY.replace("samples = 4", "samples = 2"), "two.toml")
    out = tmp_path / "out"
    run_study(one, out, executor="processes", workers=1, progress=False)
    figures = ["boxplot_rmse_position_m.png", "error_bands_short_nerov.png", "error_bands_short_bluerov.png"]
    stamps = {f: (out / f).stat().st_mtime_ns for f in figures}
    assert json.loads((out / "timing.json").read_text())["figures_drawn"] == 3
    run_study(one, out, executor="processes", workers=1, progress=False)
    assert json.loads((out / "timing.json").read_text())["figures_drawn"] == 0
    assert {f: (out / f).stat().st_mtime_ns for f in figures} == stamps
    (out / figures[1]).unlink()  # a missing figure is drawn again, alone
    run_study(one, out, executor="processes", workers=1, progress=False)
    assert json.loads((out / "timing.json").read_text())["figures_drawn"] == 1
    run_study(two, out, executor="processes", workers=1, progress=False)  # new runs: all redrawn
    assert json.loads((out / "timing.json").read_text())["figures_drawn"] == 3
