"""Reading a study file: TOML to a validated :class:`Study`. Every error
names the file and the field; a configuration the C++ core refuses, or a
perturbation that breaks a vehicle, is refused here, not halfway through
the runs."""

from __future__ import annotations

from collections.abc import Mapping
from pathlib import Path
from typing import Any

from neurov.schema import did_you_mean
from neurov.files import read_toml, shipped_or_path
from neurov.study.factory import ControllerFactory, FactoryError
from neurov.study.one_run import resolved_spec
from neurov.study.sampling import nominal_parameters, scaled
from neurov.study.spec import (
    NON_NEGATIVE,
    ENVIRONMENT_PARAMETERS,
    MAX_RUNS,
    NORMAL_TRUNCATION,
    SCENARIO_DIR,
    STUDY_DIR,
    VEHICLE_PARAMETERS,
    Perturbation,
    Study,
    StudyError,
    metric_names,
    vehicle_key,
)
from neurov import _core
from neurov.config.reading import load_scenario, read_controller
from neurov.config.scenario import ControllerSpec, Scenario, ScenarioError
from neurov.config.toml_table import TableReader
from neurov.laws.registry import build_controller

__all__ = ["load_study", "read_perturbations", "shipped_studies", "study_from_mapping", "study_path"]

def shipped_studies() -> list[str]:
    return sorted(p.stem for p in STUDY_DIR.glob("*.toml"))


def study_path(name_or_path: str | Path) -> Path:
    """A study file by path, or a shipped study by name (``robustness``)."""
    return shipped_or_path(name_or_path, STUDY_DIR, "study", StudyError)


def _scenario_path(ref: str, base: Path) -> Path:
    p = Path(ref)
    if p.suffix == ".toml":
        return p if p.is_absolute() else base / p
    return SCENARIO_DIR / f"{ref}.toml"


class _MergedReader(TableReader):
    """Reads a controller's fields merged with one vehicle's sub-table,
    naming the sub-table in errors about the fields it gave."""

    def __init__(self, base: Mapping[str, Any], over: Mapping[str, Any], where: str, origin: str,
                 vehicle: str) -> None:
        super().__init__({**base, **over}, where, origin)
        self._over = set(over)
        self._vehicle = vehicle

    def _name(self, key: str) -> str:
        root = key.split(".")[0]
        prefix = f"{self.where}.{self._vehicle}" if root in self._over else self.where
        return f"{prefix}.{key}"


def _perturbation(r: TableReader) -> Perturbation:
    known = (*VEHICLE_PARAMETERS, *ENVIRONMENT_PARAMETERS)
    name = r.string("parameter")
    if name not in known:
        hint = did_you_mean(name, known)
        raise r.error("parameter", f"expected one of {list(known)}, got {name!r}{hint}")
    dist = r.string("distribution", "uniform", choices=("uniform", "normal"))
    p: dict[str, Any] = {"parameter": name, "distribution": dist}
    if name in VEHICLE_PARAMETERS:
        rel = r.number("relative", minimum=0.0)
        # The factor must stay > 0 at its extreme: the plant must stay physical.
        bound = 1.0 if dist == "uniform" else 1.0 / NORMAL_TRUNCATION
        if rel >= bound:
            raise r.error("relative", f"expected a number < {bound:g} for a {dist} perturbation "
                          f"(the factor must stay positive), got {rel}")
        p["relative"] = rel
        if r.has("per_element"):
            if name in ("mass", "weight", "buoyancy"):
                raise r.error("per_element", f"{name!r} is a single number")
            p["per_element"] = r.boolean("per_element", True)
    else:
        if dist == "uniform":
            lo_hi = r.array("range", 2, broadcast=False)
            if lo_hi[1] < lo_hi[0]:
                raise r.error("range", f"expected [low, high] with low <= high, got {list(lo_hi)}")
            p["low"], p["high"] = float(lo_hi[0]), float(lo_hi[1])
            lowest = p["low"]
        else:
            p["mean"] = r.number("mean")
            p["std"] = r.number("std", minimum=0.0)
            lowest = p["mean"] - NORMAL_TRUNCATION * p["std"]
        if name in NON_NEGATIVE and lowest < 0:
            raise r.error("range" if dist == "uniform" else "std",
                          f"{name} must stay >= 0, but the draws reach {lowest:g}")
    r.finish()
    return Perturbation(**p)


def _perturbations(plist: Any, r: TableReader, origin: str) -> list[Perturbation]:
    if not isinstance(plist, list):
        raise r.error("perturbations", "expected an array of tables [[perturbations]]")
    perturbations = [_perturbation(TableReader(p, f"perturbations[{k}]", origin)) for k, p in enumerate(plist)]
    seen = [p.parameter for p in perturbations]
    dup = sorted({n for n in seen if seen.count(n) > 1})
    if dup:
        raise r.error("perturbations", f"{dup[0]!r} is perturbed twice")
    return perturbations


def read_perturbations(table: Any, scenarios: list[Scenario], origin: str) -> list[Perturbation]:
    """A perturbation table in the study file's form (a list of tables, as
    ``[[perturbations]]`` reads), validated as a study validates it, the
    scenarios' plants at its extremes included; StudyError naming `origin`
    and the field."""
    try:
        perturbations = _perturbations(table, TableReader({"perturbations": table}, "", origin), origin)
    except ScenarioError as e:
        raise StudyError(str(e)) from None
    _check_plants(perturbations, scenarios, origin)
    return perturbations


def study_from_mapping(data: Mapping[str, Any], origin: str = "<study>") -> Study:
    """A study from a parsed TOML table; errors name `origin` and the field."""
    r = TableReader(data, "", origin)
    base = Path(origin).parent if origin != "<study>" else Path.cwd()
    try:
        name = r.string("name", Path(origin).stem if origin != "<study>" else "study")
        description = r.string("description", "")
        seed = r.integer("seed", 0)
        samples = r.integer("samples", 1, minimum=1)
        after = r.number("after", 0.0, minimum=0.0)

        refs = r.raw("scenarios")
        if refs is None:
            raise r.error("scenarios", "missing (expected a list of scenario names or files)")
        if not isinstance(refs, list) or not refs or not all(isinstance(x, str) for x in refs):
            raise r.error("scenarios", f"expected a non-empty list of scenario names or .toml paths, got {refs!r}")
        scenarios: list[Scenario] = []
        for k, ref in enumerate(refs):
            path = _scenario_path(ref, base)
            if not path.is_file():
                shipped = sorted(p.stem for p in SCENARIO_DIR.glob("*.toml"))
                hint = did_you_mean(ref, shipped)
                raise r.error(f"scenarios[{k}]", f"no scenario {ref!r} (not a shipped name nor a file "
                              f"{path}){hint}")
            scenarios.append(load_scenario(path))
        names = [s.name for s in scenarios]
        dup = sorted({n for n in names if names.count(n) > 1})
        if dup:
            raise r.error("scenarios", f"two scenarios share the name {dup[0]!r}; names label the rows")
        vehicles = sorted({vehicle_key(s) for s in scenarios})

        ctable = r.raw("controllers")
        if not isinstance(ctable, Mapping) or not ctable:
            raise r.error("controllers", "missing (expected tables [controllers.NAME] with a 'type')")
        controllers: list[str] = []
        specs: dict[tuple[str, str], ControllerSpec] = {}
        factories: dict[str, ControllerFactory] = {}
        for key, table in ctable.items():
            where = f"controllers.{key}"
            if not isinstance(table, Mapping):
                raise StudyError(f"{origin}: {where}: expected a table")
            if "factory" in table:
                factories[key] = _factory(table, where, origin, key)
                controllers.append(key)
                continue
            common = {k: v for k, v in table.items() if not (isinstance(v, Mapping) and k != "centres")}
            per_vehicle = {k: v for k, v in table.items() if isinstance(v, Mapping) and k != "centres"}
            for v in per_vehicle:
                if v not in vehicles:
                    # A misspelt table field ("centers") lands here too.
                    hint = did_you_mean(v, [*vehicles, "centres"])
                    raise StudyError(f"{origin}: {where}.{v}: no scenario of this study uses a vehicle "
                                     f"{v!r} (vehicles: {vehicles}){hint}")
            for v in vehicles:
                if per_vehicle and v not in per_vehicle:
                    raise StudyError(f"{origin}: {where}: gives gains for {sorted(per_vehicle)} but not "
                                     f"for vehicle {v!r}; add [{where}.{v}]")
                reader = _MergedReader(common, per_vehicle.get(v, {}), where, origin, v)
                spec = read_controller(reader)
                if not spec.label:
                    spec.label = key
                specs[(key, v)] = spec
            controllers.append(key)

        perturbations = _perturbations(r.raw("perturbations", []), r, origin)

        rk = r.table_of("ranking")
        ranking = rk.string("metric", "rmse_position_m")
        also = rk.raw("also_show", [])
        if not isinstance(also, list) or not all(isinstance(x, str) for x in also):
            raise rk.error("also_show", f"expected a list of metric names, got {also!r}")
        reference = rk.string("reference", "")
        if reference and reference not in controllers:
            raise rk.error("reference", f"expected one of the study's controllers {controllers}, got {reference!r}")
        rk.finish()
        fr = r.table_of("failure")
        failure = {k: fr.number(k) for k in list(fr.table)}
        fr.finish()

        dg = r.table_of("diagnostics")
        basis_rank = dg.boolean("basis_rank", False)
        dg.finish()

        pairs: list[tuple[str, str]] = []
        h2h = r.raw("head_to_head", [])
        if not isinstance(h2h, list):
            raise r.error("head_to_head", "expected a list of [controller, controller] pairs")
        for k, pair in enumerate(h2h):
            if not (isinstance(pair, list) and len(pair) == 2 and all(x in controllers for x in pair)):
                raise r.error(f"head_to_head[{k}]", f"expected two of {controllers}, got {pair!r}")
            pairs.append((pair[0], pair[1]))
        r.finish()
    except ScenarioError as e:
        raise StudyError(str(e)) from None

    study = Study(name=name, scenarios=scenarios, controllers=controllers, controller_specs=specs, factories=factories,
                  perturbations=perturbations, samples=samples, seed=seed, after=after,
                  ranking_metric=ranking, also_show=list(also), failure=failure, head_to_head=pairs,
                  reference=reference, basis_rank=basis_rank,
                  description=description, source=origin)
    runs = len(scenarios) * len(controllers) * samples
    if runs > MAX_RUNS:
        raise StudyError(f"{origin}: samples: {len(scenarios)} scenarios x {len(controllers)} controllers x "
                         f"{samples} samples = {runs} runs, more than a study holds "
                         f"(neurov.study.spec.MAX_RUNS = {MAX_RUNS})")
    _check_metrics(study, origin)
    _check_plants(study.perturbations, study.scenarios, origin)
    _check_controllers(study, origin, {k: bool(t and any(isinstance(v, Mapping) and n != "centres"
                                                        for n, v in t.items()))
                                       for k, t in ctable.items()})
    return study


def _factory(table: Mapping[str, Any], where: str, origin: str, key: str) -> ControllerFactory:
    """[controllers.KEY] with a factory: only 'factory', 'label' and the
    keyword 'arguments' it is called with."""
    unknown = sorted(set(table) - {"factory", "label", "arguments"})
    if unknown:
        raise StudyError(f"{origin}: {where}.{unknown[0]}: a controller given by a factory takes only "
                         f"'factory', 'label' and 'arguments' (its gains are the factory's business)")
    path, label = table["factory"], table.get("label", key)
    if not isinstance(path, str) or ":" not in path:
        raise StudyError(f"{origin}: {where}.factory: expected 'module.path:function', got {path!r}")
    if not isinstance(label, str):
        raise StudyError(f"{origin}: {where}.label: expected a string, got {label!r}")
    arguments = table.get("arguments", {})
    if not isinstance(arguments, Mapping):
        raise StudyError(f"{origin}: {where}.arguments: expected a table of keyword arguments, got {arguments!r}")
    return ControllerFactory(path, label, tuple(sorted(arguments.items())))


def _check_controllers(study: Study, origin: str, per_vehicle: Mapping[str, bool]) -> None:
    """Builds every controller once per vehicle, so a configuration the C++
    refuses (say, modification = "sigma" without sigma_m) is named here and
    not in a worker halfway through the study."""
    first: dict[str, int] = {}
    for i, s in enumerate(study.scenarios):
        first.setdefault(vehicle_key(s), i)
    for j, key in enumerate(study.controllers):
        if key in study.factories:
            # Imported and called on every scenario here, so that a factory that
            # fails does so before any run starts.
            for s in study.scenarios:
                try:
                    study.factories[key].make(s)
                except FactoryError as e:
                    raise StudyError(f"{origin}: controllers.{key}.factory: {e}") from None
            continue
        for v, i in first.items():
            where = f"controllers.{key}.{v}" if per_vehicle.get(key) else f"controllers.{key}"
            try:
                build_controller(resolved_spec(study, j, i), study.scenarios[i])
            except (ValueError, TypeError) as e:
                raise StudyError(f"{origin}: {where}: {e}") from None


def _check_metrics(study: Study, origin: str) -> None:
    known = metric_names()
    checks = [(study.ranking_metric, "ranking.metric")]
    checks += [(k, f"ranking.also_show[{i}]") for i, k in enumerate(study.also_show)]
    checks += [(k, f"failure.{k}") for k in study.failure]
    for key, where in checks:
        if key not in known:
            hint = did_you_mean(key, known)
            raise StudyError(f"{origin}: {where}: unknown metric {key!r}{hint}")
    for s in study.scenarios:
        if study.after >= s.duration:
            raise StudyError(f"{origin}: after: {study.after} s leaves no samples of scenario "
                             f"{s.name!r} ({s.duration} s)")


def _check_plants(perturbations: list[Perturbation], scenarios: list[Scenario], origin: str) -> None:
    """Every scenario's vehicle must survive the extremes of the perturbation
    (a scaled mass matrix must stay positive definite, for instance)."""
    for p in perturbations:
        if p.parameter != "current_speed":
            continue
        spread = NORMAL_TRUNCATION * p.std
        low, high = (p.mean - spread, p.mean + spread) if p.distribution == "normal" else (p.low, p.high)
        for s in scenarios:
            gm = s.gauss_markov_current
            if s.current_model == _core.CurrentModel.gauss_markov and not gm.speed_min <= low <= high <= gm.speed_max:
                raise StudyError(f"{origin}: perturbations: current_speed from {low:g} to {high:g} m/s: scenario "
                                 f"{s.name!r} has a Gauss-Markov current, whose mean speed it sets, within "
                                 f"[speed_min, speed_max] = [{gm.speed_min:g}, {gm.speed_max:g}]")
    vehicle_p = [p for p in perturbations if p.is_vehicle]
    if not vehicle_p:
        return
    for s in scenarios:
        nominal = nominal_parameters(s)
        for corner in (-1.0, 1.0):
            params = dict(nominal)
            for p in vehicle_p:
                spread = p.relative * (NORMAL_TRUNCATION if p.distribution == "normal" else 1.0)
                params[p.parameter] = scaled(params[p.parameter], 1.0 + corner * spread, False)
            try:
                _core.Vehicle(**params)
            except ValueError as e:
                raise StudyError(f"{origin}: perturbations: scenario {s.name!r}: at the extreme factors "
                                 f"({'low' if corner < 0 else 'high'}) the vehicle is not valid: {e}") from None


def load_study(path: str | Path) -> Study:
    """Reads a study file (or a shipped study by name); raises
    :class:`StudyError` naming the file and the field."""
    path = study_path(path)
    return study_from_mapping(read_toml(path, StudyError, "study"), str(path))
