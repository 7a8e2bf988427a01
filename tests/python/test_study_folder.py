"""A study folder knows its study: the log's records carry the study's
fingerprint, so a lost or broken study.json neither lets another study reuse
the runs nor is mistaken for another study; a record that is not a run is
skipped with a warning naming the file and line, and redone."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from neurov.study import LOG_NAME, StudyError, load_study, run_study
from neurov.study.log import StudyLogWarning, read_log
from study_files import STUDY, write_study

ONE = STUDY.replace("samples = 4", "samples = 1")


def _run(path: Path, out: Path):  # type: ignore[no-untyped-def]
    return run_study(path, out, executor="processes", workers=1, progress=False, plots=False)


@pytest.fixture
def done(tmp_path: Path) -> tuple[Path, Path, bytes]:
    """A finished small study: its file, its folder and its runs.csv."""
    path = write_study(tmp_path, ONE, "one.toml")
    out = tmp_path / "out"
    return path, out, _run(path, out).table_path.read_bytes()


def test_another_seed_without_study_json_does_not_reuse_the_runs(done: tuple[Path, Path, bytes],
                                                                tmp_path: Path) -> None:
    path, out, _ = done
    other = write_study(tmp_path, ONE.replace("seed = 7", "seed = 8"), "other.toml")
    (out / "study.json").unlink()
    with pytest.raises(StudyError, match=r"holds runs of a different study .*study.json is missing, so which "
                                         r"field differs cannot be said"):
        _run(other, out)
    # The folder is as it was: the right study still resumes from it (and writes study.json again) ...
    assert _run(path, out).ran == 0
    # ... which then names what differs.
    with pytest.raises(StudyError, match=r"seed \(7 there, 8 here\)"):
        _run(other, out)


def test_a_different_study_names_the_field_that_differs(done: tuple[Path, Path, bytes], tmp_path: Path) -> None:
    _, out, _ = done
    cases = {
        "after = 5.0": ("after = 6.0", r"after \(the metrics window\) \(5.0 there, 6.0 here\)"),
        "relative = 0.3\n\n[[perturbations]]\nparameter = \"added_mass\"":
            ("relative = 0.4\n\n[[perturbations]]\nparameter = \"added_mass\"", r"differs in perturbations;"),
        "[controllers.nn.nerov]\nkd = [200, 200, 200, 50, 50, 50]":
            ("[controllers.nn.nerov]\nkd = [100, 200, 200, 50, 50, 50]", r"differs in controllers \(nn@nerov\)"),
    }
    for i, (old, (new, message)) in enumerate(cases.items()):
        assert old in ONE
        with pytest.raises(StudyError, match=message):
            _run(write_study(tmp_path, ONE.replace(old, new), f"c{i}.toml"), out)


def test_a_garbage_study_json_is_named_as_such(done: tuple[Path, Path, bytes], tmp_path: Path) -> None:
    path, out, table = done
    (out / "study.json").write_text("{ not json")
    # The log's records say whose runs they are: the same study resumes, and study.json is written again.
    with pytest.warns(StudyLogWarning, match=r"study.json: not readable JSON \(.*\); written again"):
        again = _run(path, out)
    assert again.ran == 0 and again.table_path.read_bytes() == table
    assert json.loads((out / "study.json").read_text())["fingerprint"] == load_study(path).fingerprint()
    (out / "study.json").write_bytes(b"\xff\xfe")
    other = write_study(tmp_path, ONE.replace("seed = 7", "seed = 8"), "other.toml")
    with pytest.raises(StudyError, match=r"study.json is not readable JSON"):
        _run(other, out)


def test_records_of_an_older_neurov_need_their_study_json(done: tuple[Path, Path, bytes]) -> None:
    path, out, table = done
    log = out / LOG_NAME
    old = [json.loads(line) for line in log.read_text().splitlines()]
    log.write_text("".join(json.dumps({k: v for k, v in r.items() if k != "study"}) + "\n" for r in old))
    assert _run(path, out).ran == 0  # study.json says whose they are
    (out / "study.json").unlink()
    with pytest.raises(StudyError, match=r"runs without their study's fingerprint .*study.json is missing"):
        _run(path, out)


def test_records_that_are_not_runs_are_skipped_with_a_warning_and_redone(done: tuple[Path, Path, bytes]) -> None:
    path, out, table = done
    log = out / LOG_NAME
    lines = log.read_bytes().splitlines(keepends=True)
    empty = json.loads(lines[1])
    empty["row"] = {}
    text = json.loads(lines[3])
    text["row"]["rmse_position_m"] = "0.1"
    lines[1] = (json.dumps(empty) + "\n").encode()
    lines[3] = (json.dumps(text) + "\n").encode()
    lines[4] = lines[4][:30] + b"\xe9" + lines[4][31:]
    log.write_bytes(b"".join(lines))
    with pytest.warns(StudyLogWarning) as caught:
        resumed = _run(path, out)
    message = str(caught[0].message)
    assert str(log) in message and "skipped 3 record(s)" in message
    assert "line 2: an empty row" in message
    assert "line 4: 'rmse_position_m' is '0.1', not a number" in message
    assert "line 5: not UTF-8 text (byte 0xe9 at column 31)" in message
    assert resumed.ran == 3 and resumed.table_path.read_bytes() == table


@pytest.mark.parametrize(("record", "reason"), [
    ('{"key": ["a", "b"]}', "no key"),
    ('[1, 2]', "a JSON list, not a record"),
    ('{"key": ["a", "pd", 0], "row": []}', "a row that is a list"),
    ('{"key": ["a", "pd", 0], "row": {"scenario": "b", "controller": "pd", "sample": 0, "vehicle": "v"}}',
     "whose scenario, vehicle, controller or sample does not match its key"),
    ('{"key": ["a", "pd", 0], "row": {"scenario": "a", "controller": "pd", "sample": 0, "vehicle": "v"}}',
     "without the metric 'rmse_position_m'"),
    ("not json", "not JSON"),
])
def test_each_kind_of_bad_record_is_named(tmp_path: Path, record: str, reason: str) -> None:
    log = tmp_path / LOG_NAME
    log.write_text(record + "\n")
    with pytest.warns(StudyLogWarning, match=rf"{LOG_NAME}: skipped 1 record\(s\) .*line 1: (a row )?{reason}"):
        assert read_log(log) == {}
