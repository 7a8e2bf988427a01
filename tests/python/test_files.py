"""Files that are not files (docs/reliability.md): a scenario, study or vehicle
path naming a device, a FIFO, a directory, a file too large or not UTF-8 gets
an error naming the file, without reading without bound or blocking."""
from __future__ import annotations

import os
import sys
from pathlib import Path

import pytest

from neurov import cli, files
from neurov.config.reading import load_scenario
from neurov.config.scenario import ScenarioError
from neurov.schema import as_dict
from neurov.study import StudyError, load_study
from neurov.config.vehicle_file import VehicleFileError, load_thrusters, load_vehicle_parameters

LOADERS = [
    pytest.param(load_scenario, ScenarioError, id="scenario"),
    pytest.param(load_study, StudyError, id="study"),
    pytest.param(load_vehicle_parameters, VehicleFileError, id="vehicle"),
    pytest.param(load_thrusters, VehicleFileError, id="vehicle-thrusters"),
]

posix_only = pytest.mark.skipif(sys.platform == "win32", reason="device files and FIFOs are POSIX")


def a_directory(tmp_path: Path) -> Path:
    folder = tmp_path / "a_folder.toml"
    folder.mkdir()
    return folder


def a_fifo(tmp_path: Path) -> Path:
    fifo = tmp_path / "pipe.toml"
    os.mkfifo(fifo)  # no writer: a plain open() would block for ever
    return fifo


def an_endless_device(tmp_path: Path) -> Path:
    device = tmp_path / "device.toml"  # a .toml name, so a study is not looked up by name
    device.symlink_to("/dev/zero")
    return device


@pytest.mark.parametrize(
    ("make", "match"),
    [
        pytest.param(a_directory, "is a directory", id="directory"),
        pytest.param(a_fifo, "FIFO", id="fifo-without-blocking", marks=posix_only),
        pytest.param(an_endless_device, "character device", id="device-without-reading", marks=posix_only),
    ],
)
@pytest.mark.parametrize(("load", "error"), LOADERS)
def test_a_path_that_is_not_a_regular_file_is_named_as_such(tmp_path: Path, load, error, make, match: str) -> None:
    path = make(tmp_path)
    with pytest.raises(error, match=match) as err:
        load(path)
    assert str(path) in str(err.value)


@pytest.mark.parametrize(("load", "error"), LOADERS)
def test_file_over_the_limit_is_refused(tmp_path: Path, load, error) -> None:
    big = tmp_path / "big.toml"
    with big.open("wb") as f:
        f.truncate(files.MAX_FILE_BYTES + 1)  # sparse: no 4 MiB written
    with pytest.raises(error, match=f"larger than {files.MAX_FILE_BYTES} bytes") as err:
        load(big)
    assert str(big) in str(err.value)


def test_file_at_the_limit_is_read(tmp_path: Path) -> None:
    exact = tmp_path / "exact.toml"
    exact.write_bytes(b"a = 1\n" + b" " * (files.MAX_FILE_BYTES - 6))
    assert files.read_text(exact).startswith("a = 1\n")
    assert len(files.read_text(exact)) == files.MAX_FILE_BYTES


@pytest.mark.parametrize(("load", "error"), LOADERS)
def test_non_utf8_file_names_the_file_and_the_byte(tmp_path: Path, load, error) -> None:
    latin1 = tmp_path / "latin1.toml"
    latin1.write_bytes('name = "caf\u00e9"\n'.encode("latin-1"))
    with pytest.raises(error, match=r"not UTF-8 text \(byte 0xe9 at offset 11\)") as err:
        load(latin1)
    assert str(latin1) in str(err.value)


@posix_only
def test_unreadable_file_names_the_file(tmp_path: Path) -> None:
    if os.geteuid() == 0:
        pytest.skip("root reads every file")
    secret = tmp_path / "secret.toml"
    secret.write_text("a = 1\n")
    secret.chmod(0)
    with pytest.raises(ScenarioError, match="cannot open") as err:
        load_scenario(secret)
    assert str(secret) in str(err.value)


def test_missing_file_is_still_worded_by_the_loader(tmp_path: Path) -> None:
    with pytest.raises(ScenarioError, match="no such scenario file"):
        load_scenario(tmp_path / "nowhere.toml")
    with pytest.raises(FileNotFoundError):
        files.read_text(tmp_path / "nowhere.toml")


@posix_only
def test_cli_run_on_dev_zero_fails_at_once_naming_it(capsys: pytest.CaptureFixture[str]) -> None:
    assert cli.main(["run", "/dev/zero"]) == 1
    err = capsys.readouterr().err
    assert "/dev/zero" in err and "character device" in err


def _nested(depth: int) -> str:
    """A key whose value nests `depth` arrays (the parser recurses on each)."""
    return "a = " + "[" * depth + "]" * depth + "\n"


@pytest.mark.parametrize(("load", "error"), LOADERS)
@pytest.mark.parametrize("text", [_nested(500), "a = " + "{b = " * 500 + "1" + "}" * 500 + "\n",
                                  ".".join(["t"] * 500) + " = 1\n", _nested(files.MAX_TOML_DEPTH)],
                         ids=["arrays-500", "inline-tables-500", "dotted-keys-500", "arrays-at-limit+1"])
def test_toml_nested_too_deep_is_named_not_a_recursion_error(tmp_path: Path, load, error, text: str) -> None:
    """500 nested arrays ended tomllib in RecursionError (a traceback from the
    command line); dotted keys parse but nest the table as deep."""
    deep = tmp_path / "deep.toml"
    deep.write_text(text, encoding="utf-8")
    with pytest.raises(error, match=f"nested more than {files.MAX_TOML_DEPTH} levels deep") as err:
        load(deep)
    assert str(deep) in str(err.value)


def test_nesting_at_the_limit_is_read(tmp_path: Path) -> None:
    at = tmp_path / "at.toml"
    at.write_text(_nested(files.MAX_TOML_DEPTH - 1), encoding="utf-8")
    assert files.read_toml(at, ValueError, "test")["a"] is not None


SHIPPED = Path(files.__file__).parent
BOM_FILES = [
    pytest.param(load_scenario, (SHIPPED / "scenarios" / "nerov_square.toml").read_bytes(), id="scenario"),
    pytest.param(load_study, b'scenarios = ["nerov_square"]\n[controllers.pd]\ntype = "pd"\n', id="study"),
    pytest.param(load_vehicle_parameters, (SHIPPED / "vehicles" / "nerov.toml").read_bytes(), id="vehicle"),
    pytest.param(load_thrusters, (SHIPPED / "vehicles" / "bluerov2_heavy.toml").read_bytes(),
                 id="vehicle-thrusters"),
]


def _contents(loaded: object) -> str:
    simulation = getattr(loaded, "simulation", None)  # a Scenario's repr is its name only
    return repr(loaded) + ("" if simulation is None else repr(as_dict(simulation)))


@pytest.mark.parametrize(("load", "text"), BOM_FILES)
def test_a_utf8_byte_order_mark_is_skipped(tmp_path: Path, load, text: bytes) -> None:
    """Editors on Windows start UTF-8 files with a BOM: tomllib alone said
    "Invalid statement (at line 1, column 1)"."""
    copy = tmp_path / "with_bom.toml"  # one path for both, as a loader may keep it
    copy.write_bytes(text)
    plain = _contents(load(copy))
    copy.write_bytes(b"\xef\xbb\xbf" + text)
    assert _contents(load(copy)) == plain


def test_utf16_is_named_as_such(tmp_path: Path) -> None:
    utf16 = tmp_path / "utf16.toml"
    utf16.write_text("a = 1\n", encoding="utf-16")  # with its BOM
    with pytest.raises(ScenarioError, match="UTF-16 text") as err:
        load_scenario(utf16)
    assert str(utf16) in str(err.value)
