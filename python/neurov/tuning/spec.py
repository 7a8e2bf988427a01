"""What a tuning is: the parameters searched per controller, the settings
of ``[tune]`` and the study the trials are judged by."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

from neurov.study.spec import StudyError

__all__ = ["AGGREGATES", "PRUNERS", "SAMPLERS", "SearchParameter", "TuneError", "TuneSettings", "Tuning"]

SAMPLERS = ("tpe", "cmaes", "gp", "random")
AGGREGATES = ("mean", "median")
# "median": Optuna's MedianPruner on the running objective after each run; "none": every trial runs whole.
PRUNERS = ("median", "none")


class TuneError(StudyError):
    """A tuning file that cannot be tuned: names the file and the field."""


@dataclass(frozen=True)
class SearchParameter:
    """One searched quantity of one controller.

    ``kind`` is ``"scale"`` (one factor on a whole vector given in the
    controller's table), ``"range"`` (the value itself; ``index`` set for one
    element of a vector) or ``"choices"`` (one of a list)."""

    key: str
    """As written in the search table: ``kp``, ``kd[2]``, ``centres.n``."""
    path: tuple[str, ...]
    """The field in the controller's table: ``("centres", "n")``."""
    kind: str
    low: float = 0.0
    high: float = 1.0
    log: bool = False
    integer: bool = False
    index: int | None = None
    choices: tuple[Any, ...] = ()
    vehicle: str | None = None
    """Set for a key ``VEHICLE.field``: that vehicle's sub-table alone."""


@dataclass(frozen=True)
class TuneSettings:
    trials: int
    objective: str
    aggregate: str = "mean"
    failure_penalty: float = 10.0
    max_failure_rate: float | None = None
    sampler: str = "tpe"
    pruner: str = "median"
    """Stops a trial whose running objective is worse than the median of the
    finished trials' at the same run (docs/tuning.md, "Pruning")."""
    seed: int = 0
    train_samples: int = 20
    test_samples: int = 50
    test_seed: int = 1
    """The plants' seed of the verdict (the study's seed draws the training plants)."""
    test_scenarios: tuple[str, ...] = ()
    hand_set_in_verdict: bool = True
    """The verdict also runs each controller with its hand-set gains, labelled so."""


@dataclass
class Tuning:
    name: str
    source: str
    settings: TuneSettings
    study_table: dict[str, Any]
    """The study part of the file (no ``[tune]``, no ``search`` tables), as read."""
    search: dict[str, list[SearchParameter]]
    """Controller key -> its searched parameters, in the file's order; a
    controller without a search table is run in the verdict as given."""
    controllers: list[str] = field(default_factory=list)
