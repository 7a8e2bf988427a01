"""The one progress bar: shown on a terminal, silent with quiet and when
stderr is not a terminal (a pipe, a log file, pytest's capture)."""

from __future__ import annotations

import io
from pathlib import Path

import numpy as np
import pytest

from neurov import cli
from neurov.progress import progress_bar, shows_progress
from neurov.config.scenario import CommandSpec, ControllerSpec, Scenario
from neurov.running.many import simulate_many


class Terminal(io.StringIO):
    def isatty(self) -> bool:
        return True


def test_bar_on_a_terminal_only() -> None:
    tty, pipe = Terminal(), io.StringIO()
    assert shows_progress(stream=tty) and not shows_progress(stream=pipe)
    assert not shows_progress(quiet=True, stream=tty)
    for stream, quiet in ((tty, False), (tty, True), (pipe, False)):
        with progress_bar(3, "work", quiet=quiet, stream=stream) as bar:
            bar.update(3)
    assert "work" in tty.getvalue() and "3/3" in tty.getvalue()
    assert pipe.getvalue() == ""


def test_quiet_bar_writes_nothing_to_a_terminal() -> None:
    tty = Terminal()
    with progress_bar(3, "work", quiet=True, stream=tty) as bar:
        bar.update(3)
    assert tty.getvalue() == ""


SHORT = Scenario(name="short", duration=2.0,
                 command=CommandSpec(type="waypoints", times=[0.0], poses=[[0.0] * 6]),
                 controller=ControllerSpec(type="pd", kp=np.ones(6), kd=np.ones(6)))


def test_simulate_many_shows_progress_on_a_terminal(monkeypatch: pytest.MonkeyPatch) -> None:
    tty = Terminal()
    monkeypatch.setattr("sys.stderr", tty)
    assert len(list(simulate_many([(SHORT, None)] * 3, progress=True))) == 3
    assert "3/3" in tty.getvalue()
    tty.seek(0)
    tty.truncate()
    assert len(list(simulate_many([(SHORT, None)] * 3))) == 3
    assert tty.getvalue() == ""


def test_study_progress_covers_runs_tables_and_plots_and_quiet_silences_it(
        tmp_path: Path, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]) -> None:
    from study_files import STUDY, write_study

    small = write_study(tmp_path, STUDY.replace("samples = 4", "samples = 1"), "one.toml")
    args = ["study", str(small), "--workers", "1", "--executor", "processes"]
    tty = Terminal()
    monkeypatch.setattr("sys.stderr", tty)
    assert cli.main([*args, "--out", str(tmp_path / "loud")]) == 0
    shown = tty.getvalue()
    assert "small: runs" in shown and "6/6" in shown
    assert "small: tables" in shown and "small: plots" in shown
    tty.seek(0)
    tty.truncate()
    assert cli.main([*args, "--out", str(tmp_path / "quiet"), "--quiet"]) == 0
    assert tty.getvalue() == ""
    # Not a terminal: no bar either, without --quiet.
    monkeypatch.undo()
    assert cli.main([*args, "--out", str(tmp_path / "piped")]) == 0
    assert capsys.readouterr().err == ""
