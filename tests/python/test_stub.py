"""The type stub neurov/_core.pyi is the one tools/generate_stubs.py writes
from the compiled module (pybind11-stubgen reading the bindings' signatures and
docstrings), so its names, parameters, properties and setters are the module's.
What generation does not guarantee is tested here: that the committed file is
up to date, that the bindings declare real types (no ``Any``) and a docstring
for everything, and that a type checker reads the module as it behaves."""

from __future__ import annotations

import ast
import difflib
import importlib.resources
import importlib.util
import re
import subprocess
import sys
from pathlib import Path
from typing import Any

import pytest

import neurov._core as core

ROOT = Path(__file__).resolve().parents[2]
STUB_FILE = importlib.resources.files("neurov") / "_core.pyi"
STUB_TEXT = STUB_FILE.read_text(encoding="utf-8")
STUB = ast.parse(STUB_TEXT)


def generator() -> Any:
    spec = importlib.util.spec_from_file_location("generate_stubs", ROOT / "tools" / "generate_stubs.py")
    assert spec and spec.loader
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_the_committed_stub_is_the_generated_one(tmp_path: Path) -> None:
    python = Path(core.__file__).resolve().parent.parent
    assert generator().main(["--out", str(tmp_path), "--python-path", str(python)]) == 0
    generated = sorted(p.name for p in tmp_path.iterdir())
    assert generated == ["_core.pyi", "_core_controllers.pyi"]
    for name in generated:
        committed = (importlib.resources.files("neurov") / name).read_text(encoding="utf-8")
        fresh = (tmp_path / name).read_text(encoding="utf-8")
        diff = "".join(difflib.unified_diff(committed.splitlines(True), fresh.splitlines(True),
                                            f"committed {name}", f"generated {name}"))
        assert not diff, f"{name} is out of date: run python tools/generate_stubs.py\n" + diff


def test_stub_and_marker_are_installed() -> None:
    assert STUB_FILE.is_file()
    assert (importlib.resources.files("neurov") / "py.typed").is_file()


def functions(tree: ast.AST) -> list[tuple[str, ast.FunctionDef]]:
    """Every def in the stub, with its qualified name."""
    out = []
    for node in tree.body:  # type: ignore[attr-defined]
        if isinstance(node, ast.FunctionDef):
            out.append((node.name, node))
        elif isinstance(node, ast.ClassDef):
            out += [(f"{node.name}.{n.name}", n) for n in node.body if isinstance(n, ast.FunctionDef)]
    return out


def dunder(qualified: str) -> bool:
    name = qualified.rsplit(".", 1)[-1]
    return name.startswith("__") and name.endswith("__")


def test_every_parameter_and_return_has_a_real_type() -> None:
    """The bindings convert array-likes, numbers and optional values
    themselves; typed_args.hpp declares what they take, so no public
    function or setter says Any or object (pybind11's dunders aside)."""
    untyped = []
    for qualified, node in functions(STUB):
        if dunder(qualified):
            continue
        args = node.args
        for arg in [*args.posonlyargs, *args.args, *args.kwonlyargs]:
            if arg.arg == "self":
                continue
            annotation = ast.unparse(arg.annotation) if arg.annotation else "<none>"
            if annotation in ("typing.Any", "object", "<none>") or "typing.Any" in annotation:
                untyped.append(f"{qualified}({arg.arg}: {annotation})")
        returns = ast.unparse(node.returns) if node.returns else "<none>"
        if returns in ("typing.Any", "object", "<none>"):
            untyped.append(f"{qualified} -> {returns}")
    assert not untyped, untyped


def enums(tree: ast.Module) -> set[str]:
    """Classes of py::enum_, whose name and value properties pybind11 writes."""
    return {node.name for node in tree.body if isinstance(node, ast.ClassDef)
            and any(isinstance(n, ast.AnnAssign) and ast.unparse(n.target) == "__members__" for n in node.body)}


def test_every_public_function_and_property_has_a_docstring() -> None:
    """The stub carries the bindings' docstrings: each public def has one
    (a setter shares its property's; an enum's name and value are pybind11's)."""
    own = {f"{enum}.{name}" for enum in enums(STUB) for name in ("name", "value")}
    missing = [
        qualified for qualified, node in functions(STUB)
        if not dunder(qualified) and not ast.get_docstring(node) and qualified not in own
        and not any(ast.unparse(d).endswith(".setter") for d in node.decorator_list)
    ]
    assert not missing, missing


def test_constants() -> None:
    assert isinstance(core.__version__, str) and core.__version__
    assert isinstance(core.THETA_NAMES, tuple) and all(isinstance(n, str) for n in core.THETA_NAMES)


def test_benchmark_helpers_are_not_in_the_core() -> None:
    """The timing helpers live in neurov._bench, built only with NEUROV_BUILD_BENCH."""
    assert not [n for n in dir(core) if n.startswith("_time")]


def test_enum_values() -> None:
    assert set(core.RobustModification.__members__) == {"none", "sigma", "e_modification", "projection"}
    assert int(core.RobustModification.none) == 0
    assert {name: int(value) for name, value in core.Status.__members__.items()} == {
        "ok": 0,
        "near_singularity": 1,
        "non_finite_input": 2,
        "invalid_argument": 3,
        "non_finite_output": 4,
    }
    assert core.Status(2) == core.Status.non_finite_input
    assert core.Status.ok.name == "ok" and core.Status.near_singularity.value == 1


def test_simulation_result_keys_match_the_stub() -> None:
    """The generator writes the result's TypedDict from RESULT_SERIES; the
    dicts the module returns have exactly its keys."""
    typed = next(n for n in STUB.body if isinstance(n, ast.ClassDef) and n.name == "_SimulationResult")
    keys = {n.target.id for n in typed.body if isinstance(n, ast.AnnAssign) and isinstance(n.target, ast.Name)}
    config = core.SimulationConfig(duration=0.4, command=core.Command(times=[0.0], poses=[[0.0] * 6]))
    result = core.run_closed_loop(core.Vehicle.nerov(), core.PDController([1.0] * 6, [1.0] * 6), config)
    assert keys == set(result)
    assert keys == set(core.Simulator(core.Vehicle.nerov(), config).result())


# A user's script: mypy must report an error on exactly the lines marked
# "error" (what the compiled module refuses or a wrong use of what it returns).
USER_SCRIPT = """\
import numpy as np
import numpy.typing as npt
from typing_extensions import assert_type

import neurov
from neurov._core import (PDConfig, PDController, PIDConfig, RbfNetwork, SimulationConfig, ThrusterFailure,
                          Vehicle, rotation, run_closed_loop)

pd = PDConfig()
assert_type(pd.kp, npt.NDArray[np.float64])
pd.kp = [1.0, 2.0, 3.0, 4.0, 5.0, 6.0]
assert_type(pd.kp, npt.NDArray[np.float64])
Vehicle.nerov().mass = 2.0  # error: read-only
pid = PIDConfig()
pid.dt = 0.1
pid.dt = "0.1"  # error: a str for a float
assert_type(pid.dt, float)
config = SimulationConfig()
assert_type(config.seed, int)
config.seed = 3
config.seed = 1.5  # error: a float for an int
assert_type(RbfNetwork([[0.0] * 24], 1.0).n_centres, int)
config.thruster_failures = [ThrusterFailure(index=1)]
assert_type(config.thruster_failures, tuple[ThrusterFailure, ...])
config.thruster_failures = [1]  # error: an int for a ThrusterFailure
config.waves = None
config.sensors = None  # error: not optional
wrong: str = pd.kp  # error: an array is not a str
rotation(0.1, 0, 0.2)
rotation("0.1", 0.0, 0.0)  # error: a str for an angle
assert_type(Vehicle.from_file("vehicle.toml"), Vehicle)
result = run_closed_loop(Vehicle.nerov(), PDController(pd), config)
assert_type(result["diverged"], bool)
assert_type(result["t"], npt.NDArray[np.float64])
result["nothing"]  # error: not a key of the result
assert_type(neurov.PDController(pd), PDController)
"""


def test_a_type_checker_reads_the_fields_as_the_module_has_them(tmp_path: Any) -> None:
    script = tmp_path / "user.py"
    script.write_text(USER_SCRIPT, encoding="utf-8")
    run = subprocess.run(
        [sys.executable, "-m", "mypy", "--strict", "--no-incremental", "--cache-dir", str(tmp_path / "cache"),
         "--no-error-summary", str(script)],
        capture_output=True, text=True, cwd=tmp_path, check=False,
    )
    reported = {int(m) for m in re.findall(r"^\S*user\.py:(\d+): error", run.stdout, flags=re.M)}
    marked = {i for i, line in enumerate(USER_SCRIPT.splitlines(), 1) if "# error" in line}
    assert reported == marked, run.stdout + run.stderr
