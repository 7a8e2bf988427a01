"""Reading a tuning file: a study file plus ``[tune]`` and, per controller, a
``search`` table. Everything is checked before any run, every error naming
the file and the field."""

from __future__ import annotations

import copy
import importlib.util
import re
from collections.abc import Collection, Mapping
from pathlib import Path
from typing import Any

from neurov.schema import did_you_mean
from neurov.files import read_toml, shipped_or_path
from neurov.config.scenario import ScenarioError
from neurov.study.reading import STUDY_DIR, study_from_mapping
from neurov.study.spec import Study, StudyError, metric_names
from neurov.tuning.space import apply_values, vehicle_tables
from neurov.tuning.spec import AGGREGATES, BUDGETS, PRUNERS, SAMPLERS, SearchParameter, TuneError, TuneSettings, Tuning
from neurov.config.toml_table import TableReader
from neurov.laws import ardusub_params as ardusub
from neurov.laws.registry import REGISTRY

__all__ = ["TUNING_DIR", "load_tuning", "tuning_from_mapping", "tuning_path", "verdict_study", "trial_study"]

TUNING_DIR = STUDY_DIR.parent / "tunings"

_KEY = re.compile(r"^([A-Za-z_]\w*(?:\.[A-Za-z_]\w*)*)(?:\[(\d+)\])?$")
# The fields of a network a search may set beside the controller type's own.
_CENTRES_FIELDS = ("n", "seed", "method")
# Samplers that need a package Optuna does not install.
_SAMPLER_NEEDS = {"cmaes": "cmaes", "gp": "torch"}


def tuning_path(name_or_path: str | Path) -> Path:
    """A tuning file by path, or a shipped tuning by name."""
    return shipped_or_path(name_or_path, TUNING_DIR, "tuning", TuneError)


def load_tuning(path: str | Path) -> Tuning:
    path = tuning_path(path)
    return tuning_from_mapping(read_toml(path, TuneError, "tuning"), str(path))


def _settings(r: TableReader, study_seed: int) -> TuneSettings:
    trials = r.integer("trials", minimum=1)
    raw = r.raw("objective", "rmse_position_m")
    if isinstance(raw, list) and len(raw) == 2 and all(isinstance(x, str) for x in raw):
        objective, effort = (_metric(r, "objective", x) for x in raw)
    elif isinstance(raw, str):
        objective, effort = _metric(r, "objective", raw), None
    else:
        raise r.error("objective", f"expected a metric or a list of two (error, effort), got {raw!r}")
    weight = None
    if r.has("effort_penalty"):
        pen = TableReader(r.raw("effort_penalty"), f"{r.where}.effort_penalty", r.origin) \
            if isinstance(r.raw("effort_penalty"), Mapping) else None
        if pen is None or effort is not None:
            raise r.error("effort_penalty", "expected { metric = \"...\", weight = ... } beside a single objective")
        effort = _metric(pen, "metric", pen.string("metric"))
        weight = pen.number("weight", positive=True)
        pen.finish()
    budget = r.string("budget", TuneSettings.budget, choices=BUDGETS)
    effort_at = _effort_at(r, effort is not None and weight is None)
    aggregate = r.string("aggregate", "mean", choices=AGGREGATES)
    penalty = r.number("failure_penalty", 10.0, positive=True)
    rate = r.number("max_failure_rate", -1.0)
    if r.has("max_failure_rate") and not 0.0 <= rate < 1.0:
        raise r.error("max_failure_rate", f"expected a share in [0, 1), got {rate}")
    sampler = r.string("sampler", "tpe", choices=SAMPLERS)
    if sampler == "cmaes" and isinstance(raw, list):
        raise r.error("sampler", "Optuna's CMA-ES searches one objective: with two, choose 'tpe', 'nsga2', "
                      "'gp' or 'random'")
    needs = _SAMPLER_NEEDS.get(sampler)
    if needs and importlib.util.find_spec(needs) is None:
        raise r.error("sampler", f"Optuna's {sampler!r} sampler needs the package {needs!r} "
                      f"(pip install {needs}), or choose 'tpe' or 'random'")
    pruner = r.string("pruner", "none" if effort is not None and weight is None else TuneSettings.pruner,
                      choices=PRUNERS)
    if pruner != "none" and effort is not None and weight is None:
        raise r.error("pruner", "Optuna's pruners judge one objective: with two, every trial runs whole "
                      "(pruner = \"none\", the default then)")
    seed = r.integer("seed", 0)
    train = r.integer("train_samples", 20, minimum=1)
    test = r.integer("test_samples", 50, minimum=1)
    # The training plants are the study's seed's; the test plants another's.
    test_seed = r.integer("test_seed", study_seed + 1)
    if test_seed == study_seed:
        raise r.error("test_seed", f"the test plants must not be the training plants: the study's seed is "
                      f"{study_seed} too")
    held = r.raw("test_scenarios", [])
    if not isinstance(held, list) or not all(isinstance(x, str) for x in held):
        raise r.error("test_scenarios", f"expected a list of scenario names or files, got {held!r}")
    hand = r.boolean("hand_set_in_verdict", True)
    r.finish()
    return TuneSettings(trials=trials, objective=objective, aggregate=aggregate, failure_penalty=penalty,
                        max_failure_rate=rate if rate >= 0 else None, sampler=sampler, pruner=pruner, seed=seed,
                        train_samples=train, test_samples=test, test_seed=test_seed,
                        test_scenarios=tuple(held), hand_set_in_verdict=hand, effort=effort,
                        effort_weight=weight, effort_at=effort_at, budget=budget)


def _metric(r: TableReader, field: str, name: str) -> str:
    known = metric_names()
    if name not in known:
        hint = did_you_mean(name, known)
        raise r.error(field, f"not a metric: {name!r}{hint} (metrics: {', '.join(known)})")
    return name


def _effort_at(r: TableReader, two: bool) -> str | tuple[tuple[str, float], ...] | None:
    """``effort_at``: a controller key, or a table of vehicle = effort."""
    if not r.has("effort_at"):
        return None
    if not two:
        raise r.error("effort_at", "reads the fronts of two objectives: give objective = [error, effort]")
    v = r.raw("effort_at")
    if isinstance(v, str):
        return v
    if isinstance(v, Mapping) and v and all(isinstance(x, (int, float)) and not isinstance(x, bool) and x > 0
                                           for x in v.values()):
        return tuple((str(k), float(x)) for k, x in v.items())
    raise r.error("effort_at", f"expected a controller's key or {{ VEHICLE = effort, ... }}, got {v!r}")


def _bounds(r: TableReader, field: str, integer: bool) -> tuple[float, float]:
    v = r.raw(field)
    if not (isinstance(v, list) and len(v) == 2 and all(isinstance(x, (int, float)) and not isinstance(x, bool)
                                                        for x in v)):
        raise r.error(field, f"expected [low, high], two numbers, got {v!r}")
    low, high = float(v[0]), float(v[1])
    if not low < high:
        raise r.error(field, f"expected low < high, got [{v[0]}, {v[1]}]")
    if integer and not (low.is_integer() and high.is_integer()):
        raise r.error(field, f"an integer range takes whole numbers, got [{v[0]}, {v[1]}]")
    return low, high


def _search_parameter(key: str, spec: Any, r: TableReader, ctype: str | None,
                      table: Mapping[str, Any]) -> SearchParameter:
    """One entry of a search table, checked against the controller type (None:
    a factory, whose keyword arguments are searched) and the values the
    controller's table gives."""
    m = _KEY.match(key)
    if m is None:
        raise r.error(key, "expected a field name, 'name[index]' or 'centres.field'")
    path = tuple(m.group(1).split("."))
    index = None if m.group(2) is None else int(m.group(2))
    vehicle = None
    if ctype is None:
        if len(path) > 1:
            raise r.error(key, "a factory's search names its keyword arguments: 'name' or 'name[index]'")
        # Whether the factory takes it is checked by calling it at both ends of the ranges.
        path = ("arguments", path[0])
        given_value = (table.get("arguments") or {}).get(path[1])
        places = [] if given_value is None else [given_value]
        name = path[1]
    else:
        # "bluerov2_heavy.kd": that vehicle's gains alone.
        vehicle = path[0] if len(path) > 1 and path[0] in vehicle_tables(table) else None
        if vehicle is not None:
            path = path[1:]
            if path[0] == "centres":
                raise r.error(key, "the network is common to the vehicles: search 'centres.FIELD'")
        kind_info = REGISTRY[ctype]
        known = [*kind_info.fields(), *kind_info.options]
        if path[0] not in known or (len(path) > 1 and (path[0] != "centres" or len(path) != 2
                                                      or path[1] not in _CENTRES_FIELDS)):
            names = known + [f"centres.{f}" for f in _CENTRES_FIELDS if "centres" in kind_info.options]
            hint = did_you_mean(m.group(1), names)
            raise r.error(key, f"unknown parameter of a {ctype!r} controller{hint} (it has: {', '.join(names)})")
        if path == ("centres",):
            raise r.error(key, "search the network's fields one by one: 'centres.n', 'centres.seed', "
                          "'centres.method'")
        if vehicle is not None:
            given_value = table[vehicle].get(path[0], table.get(path[0]))
            places = [] if given_value is None else [given_value]
        else:
            places = [t[path[0]] for t in [table, *(table[v] for v in vehicle_tables(table))] if path[0] in t]
        name = path[0]
    pr = TableReader(spec, f"{r.where}.{key}", r.origin) if isinstance(spec, Mapping) else None
    if pr is None:
        raise r.error(key, f"expected a table {{ range = [low, high] }}, {{ scale = [low, high] }} or "
                      f"{{ choices = [...] }}, got {spec!r}")
    given = [f for f in ("scale", "range", "choices") if f in spec]
    if len(given) != 1:
        raise r.error(key, f"expected exactly one of 'scale', 'range' or 'choices', got {given or 'none'}")
    kind = given[0]
    log = pr.boolean("log", False)
    integer = pr.boolean("int", False)
    out: dict[str, Any] = {"key": key, "path": path, "kind": kind, "log": log, "integer": integer, "index": index,
                           "vehicle": vehicle}
    if kind == "choices":
        choices = pr.raw("choices")
        if not isinstance(choices, list) or len(choices) < 2:
            raise pr.error("choices", f"expected a list of at least two values, got {choices!r}")
        if log or integer:
            raise pr.error("log" if log else "int", "applies to a range, not to choices")
        out["choices"] = tuple(choices)
    else:
        low, high = _bounds(pr, kind, integer and kind == "range")
        if log and low <= 0:
            raise pr.error(kind, f"a log range must lie above zero, got [{low:g}, {high:g}]")
        out["low"], out["high"] = low, high
        if ctype == "ardusub" and kind == "range" and name in ardusub.PARAMETERS:
            doc = ardusub.PARAMETERS[name]
            if low < doc.min or high > doc.max:
                raise pr.error("range", f"[{low:g}, {high:g}] leaves ArduSub's documented range of {name}, "
                               f"[{doc.min:g}, {doc.max:g}]{' ' + doc.unit if doc.unit else ''}")
        if kind == "scale":
            if integer:
                raise pr.error("int", "a scale is a real factor; use a range for an integer")
            if index is not None:
                raise pr.error("scale", f"a scale takes the whole vector: search {name!r}, or give "
                               f"{key!r} a range")
            if not places:
                raise pr.error("scale", f"scales the controller's {name!r}, which the controller's table "
                               f"does not give: write {name} = [...] there, or search it with a range")
            if any(not isinstance(v, list) for v in places):
                raise pr.error("scale", f"{name!r} is a scalar gain here; a scale takes a vector "
                               f"(use range = [low, high] for a scalar)")
    if index is not None:
        if not places or any(not isinstance(v, list) for v in places):
            raise r.error(key, f"element {index} of {name!r} needs {name} given as a vector in the "
                          f"controller's table")
        if any(index >= len(v) for v in places):
            raise r.error(key, f"index {index} is past the end of {name!r} ({min(len(v) for v in places)} "
                          f"elements)")
    pr.finish()
    return SearchParameter(**out)


def tuning_from_mapping(data: Mapping[str, Any], origin: str = "<tuning>") -> Tuning:
    """A tuning from a parsed TOML table. The study part is checked as a study
    file is; every searched parameter at both ends of its range is checked as
    a controller table is, so that a range the controller refuses is named
    here and not in a trial."""
    table: dict[str, Any] = copy.deepcopy(dict(data))
    try:
        tr = TableReader(table.pop("tune", None) or {}, "tune", origin)
        seed = table.get("seed", 0)
        settings = _settings(tr, seed if isinstance(seed, int) and not isinstance(seed, bool) else 0)
        ctable = table.get("controllers")
        search: dict[str, list[SearchParameter]] = {}
        if isinstance(ctable, Mapping):
            for ckey, ctab in ctable.items():
                if not isinstance(ctab, Mapping) or "search" not in ctab:
                    continue
                where = f"controllers.{ckey}.search"
                sr = TableReader(ctab["search"], where, origin)
                if not sr.table:
                    raise StudyError(f"{origin}: {where}: empty: name at least one parameter to search")
                ctype = None if "factory" in ctab else ctab.get("type")
                params = [_search_parameter(k, v, sr, ctype, ctab) for k, v in sr.table.items()] \
                    if ctype is None or (isinstance(ctype, str) and _known_type(ctype)) else []
                search[ckey] = params
        if not search:
            raise StudyError(f"{origin}: controllers: no controller has a search table "
                             f"([controllers.KEY.search]): nothing to tune")
        study_table = _without_search(table)
        # The study part as a study file; a bad controller or scenario is named here.
        study = study_from_mapping(study_table, origin)
    except (ScenarioError, StudyError) as e:
        raise TuneError(str(e)) from None
    if isinstance(settings.effort_at, str) and settings.effort_at not in study.controllers:
        raise TuneError(f"{origin}: tune.effort_at: {settings.effort_at!r} is not a controller of the file "
                        f"(controllers: {', '.join(study.controllers)})")
    name = study.name
    tuning = Tuning(name=name, source=origin, settings=settings, study_table=study_table, search=search,
                    controllers=list(study.controllers))
    for i, s in enumerate(settings.test_scenarios):
        try:
            verdict_study(tuning, {}, samples=1)
        except StudyError as e:
            raise TuneError(f"{origin}: tune.test_scenarios[{i}] ({s!r}): {e}") from None
    for ckey, params in search.items():
        for end in ("low", "high"):
            values = {p.key: (p.choices[0 if end == "low" else -1] if p.kind == "choices" else
                              (int(getattr(p, end)) if p.integer else getattr(p, end))) for p in params}
            try:
                trial_study(tuning, ckey, values)
            except StudyError as e:
                raise TuneError(f"{origin}: controllers.{ckey}.search: at the {end} end of every range "
                                f"({values}) the controller is refused: {e}") from None
    return tuning


def _known_type(ctype: str) -> bool:
    return ctype in REGISTRY


def _without_search(data: Mapping[str, Any]) -> dict[str, Any]:
    out = copy.deepcopy(dict(data))
    for table in (out.get("controllers") or {}).values():
        if isinstance(table, dict):
            table.pop("search", None)
    return out


def trial_study(tuning: Tuning, controller: str, values: Mapping[str, Any]) -> Study:
    """The study one trial runs: the controller with the trial's values on
    the tuning's scenarios and its training plants (the study's seed)."""
    data = copy.deepcopy(tuning.study_table)
    table = data["controllers"][controller]
    data["controllers"] = {controller: apply_values(table, tuning.search.get(controller, []), values)}
    data["samples"] = tuning.settings.train_samples
    data["head_to_head"] = []
    data.pop("ranking", None)
    return study_from_mapping(data, tuning.source)


def verdict_study(tuning: Tuning, tuned: Mapping[str, Mapping[str, Any]], *, samples: int | None = None,
                  unusable: Collection[str] = ()) -> Study:
    """The study of the verdict: every controller with its tuned table (and,
    with ``hand_set_in_verdict``, with its hand-set one beside it, key
    ``KEY_hand_set``) on the tuning's scenarios and the held-out ones, on
    the test plants (another seed than the training plants'). A controller
    in `unusable` (no feasible trial) is labelled so."""
    s = tuning.settings
    data = copy.deepcopy(tuning.study_table)
    controllers: dict[str, Any] = {}
    for key, table in data["controllers"].items():
        if key in tuned:
            t = dict(tuned[key])
            tag = "tuned, no usable trial" if key in unusable else "tuned"
            t["label"] = f"{table.get('label', key)} ({tag})"
            controllers[key] = t
            if s.hand_set_in_verdict:
                hand = dict(table)
                hand["label"] = f"{table.get('label', key)} (hand-set)"
                controllers[f"{key}_hand_set"] = hand
        else:
            controllers[key] = table
    data["controllers"] = controllers
    data["scenarios"] = list(data.get("scenarios", [])) + list(s.test_scenarios)
    data["samples"] = s.test_samples if samples is None else samples
    data["seed"] = s.test_seed
    data["name"] = f"{tuning.name}_verdict"
    # Whether a tuned network is a network: the rank of its basis along every NN run.
    data["diagnostics"] = {**data.get("diagnostics", {}), "basis_rank": True}
    study = study_from_mapping(data, tuning.source)
    # Two controllers that start from the same hand-set gains (the NN with its
    # network searched or not) need them run once.
    vehicles = sorted({v for _, v in study.controller_specs})
    seen: list[list[dict[str, Any]]] = []
    for key in [k for k in controllers if k.endswith("_hand_set")]:
        described = [{**study.controller_specs[(key, v)].describe(), "label": ""} for v in vehicles]
        if described in seen:
            del controllers[key]  # data["controllers"] is this table
        else:
            seen.append(described)
    return study if len(controllers) == len(study.controllers) else study_from_mapping(data, tuning.source)
