"""What ``neurov tune`` writes, on the days it goes wrong: a stale verdict
refreshed without touching the user's files in its folder, and a tuning
whose every trial fails said so on the console and in its files."""

from __future__ import annotations

import json
import tomllib
from pathlib import Path

import pytest

pytest.importorskip("optuna")

from tune_files import write_tiny  # noqa: E402

from neurov import cli  # noqa: E402
from neurov.tuning import tune  # noqa: E402


def test_refreshing_a_stale_verdict_keeps_the_users_files(tmp_path: Path) -> None:
    path = write_tiny(tmp_path, trials=2)
    out = tmp_path / "out"
    tune(path, out, workers=1, plots=False, progress=False)
    verdict = out / "verdict"
    old = json.loads((verdict / "study.json").read_text())["fingerprint"]
    (verdict / "notes.md").write_text("what I saw")
    (verdict / "mine").mkdir()
    (verdict / "mine" / "plot.png").write_bytes(b"png")
    # A larger budget: other best gains, a stale verdict run again.
    path.write_text(path.read_text().replace("trials = 2", "trials = 4"))
    again = tune(path, out, workers=1, plots=False, progress=False)
    assert again.verdict is not None and again.verdict.ran == again.verdict.total
    assert json.loads((verdict / "study.json").read_text())["fingerprint"] != old
    assert (verdict / "notes.md").read_text() == "what I saw"
    assert (verdict / "mine" / "plot.png").read_bytes() == b"png"


@pytest.mark.parametrize("rule", ["every run fails", "max_failure_rate"])
def test_a_tuning_whose_every_trial_fails_says_so_and_exits_3(tmp_path: Path, rule: str,
                                                              capsys: pytest.CaptureFixture[str]) -> None:
    # No gain tracks the step within a micrometre: every run fails.
    path = write_tiny(tmp_path, trials=3, fail_at=1e-6)
    if rule == "max_failure_rate":
        path.write_text(path.read_text().replace("seed = 1\n", "seed = 1\nmax_failure_rate = 0.5\n"))
    out = tmp_path / "out"
    code = cli.main(["tune", str(path), "--out", str(out), "--workers", "1", "--quiet", "--no-plots"])
    err = capsys.readouterr().err
    assert code == 3, err
    why = "no trial was feasible" if rule == "max_failure_rate" else "every run of every trial failed"
    assert f"neurov: warning: pd is not tuned: {why}" in err, err
    assert "1 of its 1 runs failed (1 x rmse_position_m > 1e-06)" in err, err
    assert f"{out / 'best.toml'} holds its least bad gains, not usable ones" in err
    assert "Traceback" not in err and err.count("\n") == 1, err
    assert why in json.loads((out / "tuning.json").read_text())["unusable"]["pd"]
    # Every file is still written.
    assert "pd" in tomllib.loads((out / "best.toml").read_text())["controllers"]
    assert "(tuned, no usable trial)" in (out / "verdict" / "league.md").read_text()
