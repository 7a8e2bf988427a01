"""``neurov identify``'s counts and output files: --substeps bounded as a
scenario's are; --out and --plot checked before the fit (an existing folder,
a folder under a file, a missing or read-only folder named as such); a full
disk named with the user's file, not an internal temporary one. Before: 10^8
substeps ran until killed, a read-only folder was found after the fit, and
errors were bare errnos naming ``.fitted-*.toml``."""

from __future__ import annotations

from pathlib import Path

import pytest

import neurov
from identify_runs import excitation_run
from neurov.cli import main
from small_disk import fill, read_only, tmpfs


def test_substeps_have_a_maximum(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["identify", "never_read.npz", "--vehicle", "nerov", "--substeps", "100000000"]) == 1
    assert (f"--substeps: expected an integer in 1..{neurov.MAX_SUBSTEPS} (neurov.MAX_SUBSTEPS"
            in capsys.readouterr().err)
    assert main(["identify", "never_read.npz", "--vehicle", "nerov", "--substeps", "0"]) == 1


@pytest.mark.parametrize(("out", "message"), [
    (".", r"--out '.*' is an existing folder; --out names a file to write"),
    ("a_file/fit.toml", r"--out '.*a_file/fit.toml': '.*a_file' is a file, not a folder"),
    ("no_folder/fit.toml", r"--out '.*no_folder/fit.toml': the folder '.*no_folder' does not exist"),
])
def test_out_is_checked_before_the_fit(tmp_path: Path, capsys: pytest.CaptureFixture[str], out: str,
                                       message: str) -> None:
    import re

    (tmp_path / "a_file").write_text("mine")
    # The log does not exist: the --out error comes first, before any log is read.
    assert main(["identify", str(tmp_path / "never_read.npz"), "--vehicle", "nerov",
                 "--out", str(tmp_path / out)]) == 1
    err = capsys.readouterr().err
    assert re.search(message, err) and "never_read" not in err and "Errno" not in err
    assert (tmp_path / "a_file").read_text() == "mine"


@pytest.fixture(scope="module")
def log(tmp_path_factory: pytest.TempPathFactory) -> Path:
    path = tmp_path_factory.mktemp("log") / "result.npz"
    excitation_run("nerov", 20.0).to_npz(path, quiet=True)
    return path


def test_a_full_disk_names_the_users_file(tmp_path: Path, capsys: pytest.CaptureFixture[str], log: Path) -> None:
    with tmpfs(tmp_path / "disk") as disk:
        fill(disk)
        for option, name in (("--out", "fit.toml"), ("--plot", "fit.png")):
            assert main(["identify", str(log), "--vehicle", "nerov", "--equation-error-only",
                         option, str(disk / name)]) == 1
            err = capsys.readouterr().err
            assert f"cannot write '{disk / name}' ({option}): No space left on device (the disk is full)" in err
            assert ".fitted-" not in err and "Errno" not in err
        assert sorted(p.name for p in disk.iterdir()) == ["filler"]  # no temporary file left
    import sys

    if "matplotlib.pyplot" in sys.modules:  # nor a figure left open
        assert sys.modules["matplotlib.pyplot"].get_fignums() == []


def test_a_read_only_folder_is_named_before_the_fit(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    with tmpfs(tmp_path / "disk") as disk:
        read_only(disk)
        assert main(["identify", str(tmp_path / "never_read.npz"), "--vehicle", "nerov",
                     "--out", str(disk / "fit.toml")]) == 1
        assert (f"--out '{disk / 'fit.toml'}': the folder '{disk}' cannot be written (a read-only file system)"
                in capsys.readouterr().err)
