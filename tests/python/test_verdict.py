"""The verdict in words (neurov.study.verdict): per vehicle the leader, by
how much and how sure against the runner-up (the paired ratio, its interval,
the Holm-corrected Wilcoxon p), at what effort, and the ties; printed last by
``neurov study``, first in league.md, and by ``neurov report``."""

from __future__ import annotations

import dataclasses
import json
import shutil
from pathlib import Path

import numpy as np
import pytest
from study_files import STUDY, write_study

from neurov import cli
from neurov.study import StudyError, load_study
from neurov.study.markdown import failed_table, read_study_folder
from neurov.study.report import league_markdown
from neurov.study.verdict import vehicle_verdicts, verdict_lines, verdict_text


def _rows(study, values, effort):  # type: ignore[no-untyped-def]
    return [{"scenario": sc.name, "controller": c, "sample": k, "rmse_position_m": v, "rmse_yaw_rad": 0.0,
             "mean_abs_tau": effort[c], "diverged": 0.0}
            for sc in study.scenarios for c, vals in values.items() for k, v in enumerate(vals)]


@pytest.fixture
def twelve(tmp_path: Path):  # type: ignore[no-untyped-def]
    return load_study(write_study(tmp_path, STUDY.replace("samples = 4", "samples = 12")))


def test_the_leader_by_how_much_how_sure_and_at_what_effort(twelve) -> None:  # type: ignore[no-untyped-def]
    rng = np.random.default_rng(2)
    base = rng.lognormal(-2.0, 0.3, 12)
    values = {"nn": base, "linear": 2.0 * base, "pd": 4.0 * base}
    verdicts = vehicle_verdicts(twelve, _rows(twelve, values, {"nn": 3.0, "linear": 1.5, "pd": 1.0}))
    assert [v.vehicle for v in verdicts] == ["nerov", "bluerov2_heavy"]
    v = verdicts[0]
    assert v.leader.controller == "nn" and [s.controller for s in v.standings] == ["nn", "linear", "pd"]
    p = v.against["linear"]
    assert p.ratio == pytest.approx(0.5) and (p.low, p.high) == pytest.approx((0.5, 0.5)) and not p.tie
    assert p.better == p.pairs == 12 and p.p_holm < 0.01
    assert v.effort["linear"].ratio == pytest.approx(2.0)
    text = verdict_text(verdicts)
    assert text.startswith("verdict (RMS position error, lower is better; 12 plants per scenario):")
    assert "nerov: NN adaptive is first, mean rank 1.00 of 3 (first on 1 of 1 scenarios)" in text
    assert "By 0.5 times the error of the runner-up, linear adaptive" in text
    assert "lower on 12 of 12 paired runs" in text and "at 2 times its effort" in text
    assert "No tie" in text


def test_a_tie_is_said_and_notes_are_appended(twelve) -> None:  # type: ignore[no-untyped-def]
    rng = np.random.default_rng(1)
    base = rng.lognormal(0.0, 0.3, 12)
    values = {"nn": base, "linear": base * np.exp(rng.normal(0, 0.1, 12)), "pd": 3.0 * base}
    v = vehicle_verdicts(twelve, _rows(twelve, values, {"nn": 1.0, "linear": 1.0, "pd": 1.0}))[0]
    assert [s.controller for s in v.tied] in (["linear"], ["nn"])
    lines = verdict_lines([dataclasses.replace(v, notes=("At equal effort: (another comparison).",))])
    assert any(line.startswith("  A tie: the plants cannot tell it from") for line in lines)
    assert lines[-1] == "  At equal effort: (another comparison)."


def test_one_plant_says_so_and_league_md_opens_with_the_verdict(tmp_path: Path) -> None:
    s = load_study(write_study(tmp_path, STUDY.replace("samples = 4", "samples = 1")))
    rows = _rows(s, {"nn": [1.0], "linear": [2.0], "pd": [3.0]}, {"nn": 1.0, "linear": 1.0, "pd": 1.0})
    assert "one run per scenario" in verdict_text(vehicle_verdicts(s, rows))
    md = league_markdown(s, rows)
    assert md.index("## Verdict") < md.index("## short_nerov")
    assert "too few paired runs for a 95 % interval" in md


def test_the_failed_runs_table_counts_them_and_says_how_far_they_ran(twelve) -> None:  # type: ignore[no-untyped-def]
    import pandas as pd

    values = {"nn": [0.1] * 12, "linear": [0.1] * 9 + [0.6, 0.8, 2.0], "pd": [0.1] * 11 + [float("inf")]}
    rows = pd.DataFrame(_rows(twelve, values, {"nn": 1.0, "linear": 1.0, "pd": 1.0}))
    rows.loc[(rows["controller"] == "pd") & (rows["sample"] == 11), "diverged"] = 1.0
    lines = failed_table(twelve, rows).splitlines()
    assert lines[0].startswith("failed runs of 12 per scenario and controller; RMS position error [m]")
    body = [line for line in lines if line.startswith("| ") and not line.startswith("| scenario")]
    first = twelve.scenarios[0].name
    assert f"| {first} | {twelve.label('linear')} | 3 of 12 | 0 | 0.8 | 2 |" in body  # over the bound of 0.5
    assert f"| {first} | {twelve.label('pd')} | 1 of 12 | 1 | - | - |" in body        # diverged: no value
    assert not any(twelve.label("nn") in line for line in body)
    assert len(body) == 2 * len(twelve.scenarios)
    calm = pd.DataFrame(_rows(twelve, {"nn": [0.1] * 12}, {"nn": 1.0}))
    assert failed_table(twelve, calm).splitlines()[-1] == "| (none) | | | | | |"


def test_cli_study_lists_what_it_wrote_then_the_verdict_and_says_each_step_when_piped(
        tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    small = write_study(tmp_path, STUDY.replace("samples = 4", "samples = 1"), "one.toml")
    assert cli.main(["study", str(small), "--out", str(tmp_path / "out"), "--workers", "1",
                     "--executor", "processes", "--no-plots"]) == 0
    captured = capsys.readouterr()
    out = captured.out
    assert captured.err == ""  # no bar when piped ...
    assert out.index("small: runs: 6 runs") < out.index("small: tables: 3 files")  # ... a line per step
    for name in ("runs.csv", "summary.csv", "league.md", "runs.jsonl", "study.json", "timing.json"):
        assert name in out.split("wrote to", 1)[1]
    assert out.rstrip().splitlines()[-1].startswith("  ")  # the verdict's last line comes last
    assert out.index("wrote to") < out.index("verdict (RMS position error")


def test_report_prints_the_folder_tables_and_refuses_another_study_version(tmp_path: Path,
                                                                           capsys: pytest.CaptureFixture[str]) -> None:
    small = write_study(tmp_path, STUDY.replace("samples = 4", "samples = 1"), "one.toml")
    out = tmp_path / "out"
    assert cli.main(["study", str(small), "--out", str(out), "--workers", "1", "--executor", "processes",
                     "--no-plots", "--quiet"]) == 0
    capsys.readouterr()
    assert cli.main(["report", str(out), "--table", "medians"]) == 0
    table = capsys.readouterr().out
    assert "RMS position error [m], one run each" in table and "| mean rank |" in table
    assert cli.main(["report", str(out), "--table", "league"]) == 0
    assert capsys.readouterr().out == (out / "league.md").read_text()
    # One controller against another, per scenario: "k of n, median ratio" in the ranking metric and the next.
    study = load_study(small)
    first, second = study.controllers[:2]
    assert cli.main(["report", str(out), "--table", "versus", "--versus", f"{first},{second}"]) == 0
    rows = [r for r in capsys.readouterr().out.splitlines() if r.startswith("| ") and " of 1, " in r]
    assert len(rows) == len(study.scenarios) and rows[0].count(" of 1, ") == 1 + len(study.also_show[:1])
    assert cli.main(["report", str(out), "--table", "failed"]) == 0
    assert capsys.readouterr().out.startswith("failed runs of 1 per scenario and controller")
    assert cli.main(["report", str(out), "--table", "versus", "--versus", f"{first},nobody"]) == 1
    assert "'nobody' is not a controller of study 'small'" in capsys.readouterr().err
    with pytest.raises(SystemExit):
        cli.main(["report", str(out), "--table", "versus"])
    # The study file changed since (another seed): the folder's runs are not of it.
    meta = json.loads((out / "study.json").read_text())
    small.write_text(small.read_text().replace("seed = 7", "seed = 8"))
    with pytest.raises(StudyError, match=r"another version of study 'small' \(differs in seed"):
        read_study_folder(out)
    assert meta["name"] == "small"
    shutil.rmtree(out)


def test_cli_tune_lists_its_files_ends_with_the_verdict_and_report_reads_its_folder(
        tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    from test_tune import write

    out = tmp_path / "out"
    assert cli.main(["tune", str(write(tmp_path, trials=3)), "--out", str(out), "--workers", "1",
                     "--no-plots"]) == 0
    text = capsys.readouterr().out
    assert "trials.csv" in text and "best.toml" in text and "tuning.db" in text
    assert text.index("verdict study on") < text.index("verdict of the tuning (RMS position error")
    assert text.rstrip().splitlines()[-1].startswith("  ")
    assert cli.main(["report", str(out), "--table", "verdict"]) == 0
    assert capsys.readouterr().out.startswith("- bluerov2_heavy: pd (tuned) is first")
    assert cli.main(["report", str(out), "--table", "league"]) == 0
    assert capsys.readouterr().out == (out / "verdict" / "league.md").read_text()
