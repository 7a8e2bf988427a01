"""What a tuning is: the parameters searched per controller, the settings
of ``[tune]`` and the study the trials are judged by."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

from neurov.study.spec import StudyError

__all__ = ["AGGREGATES", "BUDGETS", "PRUNERS", "SAMPLERS", "SearchParameter", "TuneError", "TuneSettings", "Tuning"]

SAMPLERS = ("tpe", "cmaes", "gp", "random", "nsga2")
AGGREGATES = ("mean", "median")
# "median": Optuna's MedianPruner on the running objective after each run; "none": every trial runs whole.
PRUNERS = ("median", "none")
# What ``trials`` counts (docs/tuning.md, "Budgets"): trials started (pruned ones
# included), trials completed (pruned ones not counted), or runs finished
# (``trials`` x the runs of a whole trial; a pruned trial's runs counted as run).
BUDGETS = ("trials_started", "trials_completed", "runs_finished")


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
    effort: str | None = None
    """The second objective (``objective = [error, effort]``): each controller
    gets its front of error against effort (docs/tuning.md, "Error and effort")."""
    effort_weight: float | None = None
    """Set with ``effort``: one objective, error + effort_weight x effort run by run
    (``[tune] effort_penalty = { metric, weight }``)."""
    effort_at: str | tuple[tuple[str, float], ...] | None = None
    """Where the fronts are read, per vehicle: a controller key (its hand-set
    gains' effort on the training plants) or (vehicle, effort) pairs."""
    budget: str = "trials_started"
    """What ``trials`` counts: one of :data:`BUDGETS`."""

    @property
    def two_objectives(self) -> bool:
        """Error and effort searched together (a front per controller)."""
        return self.effort is not None and self.effort_weight is None

    @property
    def objectives(self) -> tuple[str, ...]:
        return (self.objective, self.effort) if self.two_objectives else (self.objective,)


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
