"""The shipped tuned leagues: every built-in controller is searched in each
(a controller added to the core and not to a league fails here, unless the
league's entry below says why it is left out), and a seed spread's ranks
say how often they held and whether the order is settled."""

from __future__ import annotations

from pathlib import Path

import pandas as pd
import pytest

from neurov._core import BUILT_IN_CONTROLLERS
from neurov.tuning import load_tuning
from neurov.tuning.reading import TUNING_DIR
from neurov.tuning.seeds import rank_spread, spread_words
from neurov.tuning.tables import markdown_table

# Built-in controllers a shipped tuned league leaves out, each with its reason
# (for example a controller that cannot fly that league's vehicles); docs/tuning.md.
_ARDUSUB_FRAMES = ("ArduSub mixes its motors for the BlueROV2 frames only and NEROV flies none of them; "
                   "ardusub_league tunes it on the BlueROV2 Heavy")
LEFT_OUT: dict[str, dict[str, str]] = {
    "tuned_league": {"ardusub": _ARDUSUB_FRAMES},
    "tuned_realism": {"ardusub": _ARDUSUB_FRAMES},
}


@pytest.mark.parametrize("path", sorted(TUNING_DIR.glob("*.toml")), ids=lambda p: p.stem)
def test_every_built_in_controller_is_tuned_in_every_shipped_league(path: Path) -> None:
    tuning = load_tuning(path)
    tables = tuning.study_table["controllers"]
    searched = {tables[k].get("type") for k in tuning.search}
    left_out = LEFT_OUT.get(path.stem, {})
    missing = sorted(set(BUILT_IN_CONTROLLERS) - searched - set(left_out))
    assert not missing, (f"{path.name} does not tune the built-in controller(s) {missing}: add them with a "
                         f"search table, or list them in LEFT_OUT[{path.stem!r}] with the reason")
    for name, reason in left_out.items():
        assert name in BUILT_IN_CONTROLLERS and name not in searched, f"{path.stem}: {name!r} listed for nothing"
        assert len(reason.split()) >= 3, f"{path.stem}: say why {name!r} is left out"


def _seed(folder: Path, ranks: dict[tuple[str, str], int]) -> Path:
    folder.mkdir(parents=True)
    pd.DataFrame([{"scenario": s, "controller": c, "rank": r, "median": 0.1 * r}
                  for (s, c), r in ranks.items()]).to_csv(folder / "equal_effort.csv", index=False)
    return folder


def test_a_seed_spread_counts_how_often_each_rank_held(tmp_path: Path) -> None:
    a = {("sq", "nn"): 1, ("sq", "pid"): 2, ("helix", "nn"): 1, ("helix", "pid"): 2}
    b = {("sq", "nn"): 2, ("sq", "pid"): 1, ("helix", "nn"): 1, ("helix", "pid"): 2}
    folders = [_seed(tmp_path / "seed1", a), _seed(tmp_path / "seed2", a), _seed(tmp_path / "seed3", b)]
    spread = rank_spread(folders).set_index(["scenario", "controller"])
    assert spread.loc[("sq", "nn"), "ranks"] == "1 1 2"
    assert spread.loc[("sq", "nn"), ["modal_rank", "held", "seeds"]].tolist() == [1, 2, 3]
    assert spread.loc[("helix", "pid"), ["modal_rank", "held"]].tolist() == [2, 3]
    words = spread_words(spread.reset_index())
    assert "not settled on 1 of 2 scenarios: sq (nn, pid moved)" in words
    assert "Rank 1 in every seed: nn on 1 scenario(s)" in words
    assert "Rank 1 changed with the seed on sq: nn in 2 of 3 seeds, pid in 1 of 3 seeds: not settled." in words
    settled = spread_words(rank_spread(folders[:2]))
    assert "the order is settled" in settled
    table = markdown_table(folders, "spread")
    assert "| nn | 1 1 2 (1: 2 of 3) | 1 1 1 (1: 3 of 3) |" in table and "not settled" in table


def test_cli_tune_table_prints_the_spread_and_names_a_bad_folder(
        tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    from neurov import cli

    a = {("sq", "nn"): 1, ("sq", "pid"): 2}
    folders = [str(_seed(tmp_path / f"seed{i}", a)) for i in (1, 2)]
    assert cli.main(["tune-table", *folders, "--table", "spread"]) == 0
    assert "| nn | 1 1 (1: 2 of 2) |" in capsys.readouterr().out
    assert cli.main(["tune-table", str(tmp_path / "nowhere"), "--table", "budget"]) == 1
    assert "argument 'folders'" in capsys.readouterr().err


def test_cli_tune_seed_replaces_the_files_seed(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    pytest.importorskip("optuna")
    import json

    from test_tune import write

    from neurov import cli

    path = write(tmp_path, trials=2)
    assert cli.main(["tune", str(path), "--out", str(tmp_path / "seed7"), "--seed", "7", "--workers", "1",
                     "--no-verdict", "--no-plots", "--quiet"]) in (0, None)
    settings = json.loads((tmp_path / "seed7" / "tuning.json").read_text())["settings"]
    assert settings["seed"] == 7 and load_tuning(path).settings.seed == 1
    out = capsys.readouterr().out
    assert "budget: 2 trials started" in out and "pd: 2 trials started, 0 pruned, 2 completed, 6 runs finished" in out
