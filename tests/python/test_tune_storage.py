"""``neurov tune`` on a broken storage or output folder: a garbage,
truncated, read-only or folder ``tuning.db``, a read-only output folder,
``--out`` naming a file and a full disk (a small tmpfs the test mounts; CI
runs as root) each end in one line naming the user's path and what was
expected, exit status 1, and lose no finished trial."""

from __future__ import annotations

import contextlib
import os
import shutil
import sqlite3
import subprocess
from pathlib import Path

import pytest

pytest.importorskip("optuna")

from small_disk import tmpfs  # noqa: E402
from tune_files import write_tiny  # noqa: E402

from neurov import cli  # noqa: E402


def tune_cli(path: Path, out: Path, capsys: pytest.CaptureFixture[str], trials: int | None = None) -> tuple[int, str]:
    if trials is not None:
        text = path.read_text()
        path.write_text(text[:text.index("trials = ")] + f"trials = {trials}\n" +
                        text[text.index("objective = "):])
    code = cli.main(["tune", str(path), "--out", str(out), "--workers", "1", "--quiet", "--no-verdict",
                     "--no-plots"])
    err = capsys.readouterr().err
    return code, err


def complete_trials(db: Path) -> list[tuple[int, float]]:
    with contextlib.closing(sqlite3.connect(db)) as c:
        return c.execute("SELECT t.number, p.param_value FROM trials t JOIN trial_params p USING (trial_id) "
                         "WHERE t.state = 'COMPLETE' ORDER BY t.number").fetchall()


def one_line(err: str) -> str:
    assert "Traceback" not in err and err.count("\n") == 1, err
    return err


@pytest.fixture
def finished(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> tuple[Path, Path]:
    """A finished tuning of 3 trials: the tuning file and its output folder."""
    path = write_tiny(tmp_path, trials=3)
    out = tmp_path / "out"
    assert tune_cli(path, out, capsys) == (0, "")
    return path, out


@pytest.mark.parametrize(("damage", "expected"), [
    ("garbage", "not a tuning's storage (an SQLite database written by neurov tune): its first bytes are not"),
    ("truncated", "not a tuning's storage (an SQLite database written by neurov tune): truncated (3000 bytes of "
                  "the "),
    ("folder", "is a folder; the tuning's storage must be a file"),
])
def test_a_broken_storage_is_named_with_what_was_expected(finished: tuple[Path, Path], damage: str, expected: str,
                                                          capsys: pytest.CaptureFixture[str]) -> None:
    path, out = finished
    db = out / "tuning.db"
    for side in ("-wal", "-shm"):
        Path(f"{db}{side}").unlink(missing_ok=True)
    if damage == "garbage":
        db.write_bytes(os.urandom(5000))
    elif damage == "truncated":
        db.write_bytes(db.read_bytes()[:3000])
    else:
        db.unlink()
        db.mkdir()
        (db / "notes.txt").write_text("mine")
    code, err = tune_cli(path, out, capsys)
    assert code == 1
    assert f"neurov: error: {db.resolve()}: {expected}" in one_line(err), err
    if damage == "folder":
        assert (db / "notes.txt").read_text() == "mine"


def test_out_naming_a_file_is_named_as_such(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    path = write_tiny(tmp_path)
    (tmp_path / "afile").write_text("mine")
    code, err = tune_cli(path, tmp_path / "afile", capsys)
    assert code == 1
    assert f"output folder '{tmp_path / 'afile'}' is an existing file, not a folder" in one_line(err)
    assert (tmp_path / "afile").read_text() == "mine"


def read_only(path: Path) -> None:
    """`path` (a folder or a file) made read-only, for root too: bound onto itself read-only."""
    for args in (["mount", "--bind", str(path), str(path)], ["mount", "-o", "remount,ro,bind", str(path)]):
        r = subprocess.run(args, capture_output=True, text=True)
        if r.returncode:
            pytest.skip(f"{' '.join(args[:3])} is not permitted here: {r.stderr.strip()}")


@pytest.mark.parametrize("what", ["folder", "storage"])
def test_a_read_only_folder_or_storage_is_named(tmp_path: Path, what: str, capsys: pytest.CaptureFixture[str]) -> None:
    path = write_tiny(tmp_path, trials=3)
    with tmpfs(tmp_path / "disk", 8192) as disk:
        out = disk / "out"
        assert tune_cli(path, out, capsys) == (0, "")
        before = complete_trials(out / "tuning.db")
        try:
            read_only(out if what == "folder" else out / "tuning.db")
            code, err = tune_cli(path, out, capsys, trials=5)
        finally:
            subprocess.run(["umount", str(out if what == "folder" else out / "tuning.db")], check=False)
        assert code == 1
        one_line(err)
        if what == "folder":
            assert f"output folder '{out}' is not writable" in err, err
        else:
            assert f"{(out / 'tuning.db').resolve()}: the tuning's storage cannot be written (a read-only file " \
                   "or folder)" in err, err
        assert complete_trials(out / "tuning.db") == before


def fill(disk: Path, leave: int = 0) -> Path:
    """Fills `disk` but `leave` bytes; returns the filler file."""
    filler = disk / "filler"
    with filler.open("wb") as f:
        room = shutil.disk_usage(disk).free - leave
        with contextlib.suppress(OSError):
            f.write(b"\0" * max(0, room))
            f.flush()
    return filler


def test_a_full_disk_is_named_and_the_finished_trials_are_kept(tmp_path: Path,
                                                               capsys: pytest.CaptureFixture[str]) -> None:
    path = write_tiny(tmp_path, trials=4)
    with tmpfs(tmp_path / "disk", 4096) as disk:
        out = disk / "out"
        assert tune_cli(path, out, capsys) == (0, "")
        first = complete_trials(out / "tuning.db")
        # Full from the start, and full half-way through a larger budget.
        for leave, trials in ((0, 8), (150_000, 1000)):
            filler = fill(disk, leave)
            code, err = tune_cli(path, out, capsys, trials=trials)
            assert code == 1
            assert f"neurov: error: the disk holding {out} is full (no space left on device" in one_line(err)
            assert f"the trials finished so far are kept in {out / 'tuning.db'}" in err
            kept = complete_trials(out / "tuning.db")
            assert kept[:len(first)] == first
            filler.unlink()
        assert len(kept) > len(first)  # the second filled up during the trials
        # With room again, the same command resumes: the trial the full disk
        # stopped is run again and the budget ends finished.
        code, err = tune_cli(path, out, capsys, trials=len(kept) + 2)
        assert code == 0, err
        assert complete_trials(out / "tuning.db")[:len(kept)] == kept
        assert len(complete_trials(out / "tuning.db")) == len(kept) + 2
