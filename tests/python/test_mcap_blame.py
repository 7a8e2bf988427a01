"""An MCAP recording whose ``scenario`` metadata is not JSON, or whose
scenario attachment is bad, is named as the fault: the error names the MCAP
(before: a raw JSONDecodeError, or a ScenarioError blaming the scenario file
the recording was first read from, a shipped one say)."""

from __future__ import annotations

import json
import re
from pathlib import Path

import pytest

pytest.importorskip("mcap")
pytest.importorskip("mcap_ros2")

import neurov  # noqa: E402
from neurov.errors import RecordingError  # noqa: E402
from neurov.study.spec import SCENARIO_DIR  # noqa: E402


def _parts(folder: Path) -> tuple[dict[str, bytes], dict[str, dict[str, str]]]:
    from mcap.reader import make_reader

    text = (SCENARIO_DIR / "bluerov2_depth_step.toml").read_text(encoding="utf-8")
    (folder / "depth_step.toml").write_text(re.sub(r"(?m)^duration = .*$", "duration = 1.0", text))
    run = neurov.simulate(neurov.load_scenario(folder / "depth_step.toml"))
    run.to_mcap(folder / "good.mcap")
    with open(folder / "good.mcap", "rb") as f:
        reader = make_reader(f)
        return ({a.name: a.data for a in reader.iter_attachments()},
                {m.name: dict(m.metadata) for m in reader.iter_metadata()})


def _write(path: Path, attachments: dict[str, bytes], metadata: dict[str, dict[str, str]]) -> Path:
    from mcap.writer import Writer

    with open(path, "wb") as f:
        writer = Writer(f)
        writer.start()
        for name, data in attachments.items():
            writer.add_attachment(create_time=0, log_time=0, name=name, media_type="application/octet-stream",
                                  data=data)
        for name, values in metadata.items():
            writer.add_metadata(name, values)
        writer.finish()
    return path


def test_a_recording_with_bad_scenario_parts_names_the_mcap(tmp_path: Path) -> None:
    attachments, metadata = _parts(tmp_path)
    assert neurov.load_result(_write(tmp_path / "copy.mcap", attachments, metadata)).t[-1] == 1.0
    shipped = str(tmp_path / "depth_step.toml")
    assert metadata["neurov"]["source"] == shipped

    bad_meta = json.loads(json.dumps(metadata))
    bad_meta["scenario"]["describe"] = "{not json"
    with pytest.raises(RecordingError, match=r"meta\.mcap: metadata scenario: describe: not JSON"):
        neurov.load_result(_write(tmp_path / "meta.mcap", attachments, bad_meta))

    bad_scenario = {**attachments, "scenario.toml": b'name = "x"\nduration = "long"\n'}
    with pytest.raises(RecordingError, match=r"attachment\.mcap: attachment scenario\.toml \(the run's scenario, "
                                             r"read from .*depth_step\.toml\): duration: expected a "
                                             r"number") as err:
        neurov.load_result(_write(tmp_path / "attachment.mcap", bad_scenario, metadata))
    assert not str(err.value).startswith(shipped)
