"""A run's output folder holds one run (issue 23, item 4): `neurov run --out`
and `neurov paper --out` stage their files and put them in place at the end;
a stopped run is kept beside, marked partial; a full disk names the file."""

from __future__ import annotations

import errno
import json
import os
from pathlib import Path

import numpy as np
import pytest

from neurov import cli
from neurov.paper import experiments as paper
from neurov.results.export import CsvWriter
from neurov.running.stream import _Sinks
from square_pd import square_pd_scenario

SHORT = square_pd_scenario("short_pd", 4.0)


@pytest.fixture
def scenario(tmp_path: Path) -> Path:
    path = tmp_path / "short.toml"
    path.write_text(SHORT, encoding="utf-8")
    return path


def _contents(folder: Path) -> dict[str, bytes]:
    return {p.name: p.read_bytes() for p in sorted(folder.iterdir())}


def _umask() -> int:
    mask = os.umask(0)
    os.umask(mask)
    return mask


def _no_staging_left(parent: Path) -> None:
    assert not [p.name for p in parent.iterdir() if ".running-" in p.name or ".old-" in p.name]


def test_interrupted_second_run_leaves_the_first_whole(scenario: Path, tmp_path: Path,
                                                        monkeypatch: pytest.MonkeyPatch,
                                                        capsys: pytest.CaptureFixture[str]) -> None:
    out = tmp_path / "out"
    assert cli.main(["run", str(scenario), "--out", str(out)]) == 0
    assert out.stat().st_mode & 0o777 == 0o777 & ~_umask()  # a folder as mkdir makes it
    first = _contents(out)
    assert json.loads(first["metrics.json"])["partial"] is False
    add = _Sinks.add

    def add_then_ctrl_c(self: _Sinks, raw: dict[str, object]) -> int:
        add(self, raw)
        raise KeyboardInterrupt

    monkeypatch.setattr(_Sinks, "add", add_then_ctrl_c)
    capsys.readouterr()
    assert cli.main(["run", str(scenario), "--out", str(out)]) == 130
    err = capsys.readouterr().err
    assert _contents(out) == first  # the old run, whole
    kept = tmp_path / "out.partial"
    assert f"'{out}' is unchanged" in err and f"kept in '{kept}'" in err and "partial" in err
    assert sorted(p.name for p in kept.iterdir()) == ["metrics.json", "result.csv"]
    m = json.loads((kept / "metrics.json").read_text())
    assert m["partial"] is True and m["partial_reason"] == "interrupted (Ctrl-C)"
    assert m["rows_simulated"] == m["rows_in_result_csv"] == 21 and m["simulated_to_s"] == pytest.approx(4.0)
    assert m["result_csv_to_s"] == pytest.approx(4.0) and "result.csv (rows to t = 4 s)" in err
    _no_staging_left(tmp_path)


def test_full_disk_names_the_file_and_what_was_kept(scenario: Path, tmp_path: Path,
                                                     monkeypatch: pytest.MonkeyPatch,
                                                     capsys: pytest.CaptureFixture[str]) -> None:
    def full(self: CsvWriter, columns: object, progress: object = None) -> None:
        raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC))

    monkeypatch.setattr(CsvWriter, "write", full)
    out = tmp_path / "out"
    assert cli.main(["run", str(scenario), "--out", str(out)]) == 1
    err = capsys.readouterr().err
    assert "cannot write result.csv: No space left on device (the disk is full)" in err
    assert f"'{out}' was not created" in err and "out.partial" in err and "metrics.json" in err
    assert not out.exists()
    m = json.loads((tmp_path / "out.partial" / "metrics.json").read_text())
    assert m["partial"] is True and "No space left on device" in m["partial_reason"]
    _no_staging_left(tmp_path)


def test_a_folder_with_other_files_keeps_them_and_holds_one_run(scenario: Path, tmp_path: Path) -> None:
    out = tmp_path / "mine"
    out.mkdir()
    (out / "notes.txt").write_text("keep me")
    (out / "xy.png").write_bytes(b"an older run's figure")
    # This run writes no figures: the older run's are not left beside its files.
    assert cli.main(["run", str(scenario), "--out", str(out)]) == 0
    assert sorted(p.name for p in out.iterdir()) == ["metrics.json", "notes.txt", "result.csv", "result.npz",
                                                    "scenario.toml"]
    assert (out / "notes.txt").read_text() == "keep me"
    _no_staging_left(tmp_path)
    _no_staging_left(out)


def test_rerun_replaces_an_old_run_folder_whole(scenario: Path, tmp_path: Path) -> None:
    out = tmp_path / "out"
    assert cli.main(["run", str(scenario), "--out", str(out)]) == 0
    (out / "xy.png").write_bytes(b"an older run's figure")
    assert cli.main(["run", str(scenario), "--out", str(out)]) == 0
    assert sorted(p.name for p in out.iterdir()) == ["metrics.json", "result.csv", "result.npz", "scenario.toml"]
    with np.load(out / "result.npz") as data:
        assert len(data["t"]) == 21
    _no_staging_left(tmp_path)


def test_symlink_loop_as_out_is_named(scenario: Path, tmp_path: Path,
                                      capsys: pytest.CaptureFixture[str]) -> None:
    loop = tmp_path / "loop"
    os.symlink(loop, loop)
    assert cli.main(["run", str(scenario), "--out", str(loop)]) == 1
    assert f"output folder '{loop}' is a symbolic link loop" in capsys.readouterr().err
    dangling = tmp_path / "dangling"
    os.symlink(tmp_path / "nowhere", dangling)
    assert cli.main(["run", str(scenario), "--out", str(dangling)]) == 1
    assert "is a symbolic link to" in capsys.readouterr().err


def test_paper_on_a_full_disk_leaves_the_old_results(tmp_path: Path, monkeypatch: pytest.MonkeyPatch,
                                                     capsys: pytest.CaptureFixture[str]) -> None:
    shipped = paper.paper_scenario
    monkeypatch.setattr(paper, "paper_scenario", lambda name: shipped(name).replace(duration=2.0))
    monkeypatch.setattr(paper, "SWEEP_AMPLITUDES", (5.0,))
    monkeypatch.setattr(paper, "SWEEP_FREQUENCIES", (0.05,))
    out = tmp_path / "paper"
    out.mkdir()
    for name in paper.OUTPUT_NAMES:  # an earlier paper run's files
        (out / name).write_bytes(f"old {name}".encode())
    first = _contents(out)

    def full(*args: object) -> None:
        raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC))

    monkeypatch.setattr(paper, "_write_summary", full)
    assert cli.main(["paper", "--out", str(out)]) == 1
    err = capsys.readouterr().err
    assert "cannot write summary.md: No space left on device" in err and f"'{out}' is unchanged" in err
    assert _contents(out) == first
    kept = tmp_path / "paper.partial"
    assert json.loads((kept / "metrics.json").read_text())["partial"] is True
    assert (kept / "fig3_xy.png").is_file()
    _no_staging_left(tmp_path)


def test_a_full_disk_while_writing_the_npz_keeps_no_broken_archive(scenario: Path, tmp_path: Path,
                                                                    monkeypatch: pytest.MonkeyPatch,
                                                                    capsys: pytest.CaptureFixture[str]) -> None:
    import shutil

    def full(*args: object, **kwargs: object) -> None:
        raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC))

    monkeypatch.setattr(shutil, "copyfileobj", full)  # how NpzWriter streams each array in
    out = tmp_path / "out"
    assert cli.main(["run", str(scenario), "--out", str(out)]) == 1
    assert "cannot write result.npz: No space left on device" in capsys.readouterr().err
    kept = tmp_path / "out.partial"
    assert sorted(p.name for p in kept.iterdir()) == ["metrics.json", "result.csv"]


def test_out_dot_writes_into_the_current_folder(scenario: Path, tmp_path: Path,
                                               monkeypatch: pytest.MonkeyPatch) -> None:
    here = tmp_path / "here"
    here.mkdir()
    monkeypatch.chdir(here)
    assert cli.main(["run", str(scenario), "--out", "."]) == 0
    assert sorted(p.name for p in here.iterdir()) == ["metrics.json", "result.csv", "result.npz", "scenario.toml"]
    assert Path.cwd() == here
    _no_staging_left(tmp_path)
