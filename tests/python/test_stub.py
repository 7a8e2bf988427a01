"""The type stub neurov/_core.pyi matches the compiled module: the same names,
the same parameters (read from pybind11's signatures), static methods,
properties and property setters where the module has them. mypy's stubtest
checks names but cannot see a pybind11 function's parameters; this test can.

The stub re-exports its names from stub-only pieces, neurov/_core_stubs/*.pyi
(``from ._core_stubs.model import Vehicle as Vehicle``), and writes a property
as a descriptor: ``kp: _ArrayField = ...`` (an alias of ``_Field[get, set]``)
has a setter, ``mass: _ReadOnly[float] = ...`` (``_Field[get, Never]``) none."""

from __future__ import annotations

import ast
import importlib.resources
import inspect
import re
import subprocess
import sys
from typing import Any, NamedTuple

import pytest

import neurov._core as core

STUB_FILE = importlib.resources.files("neurov") / "_core.pyi"
STUB = ast.parse(STUB_FILE.read_text(encoding="utf-8"))
PIECES = importlib.resources.files("neurov") / "_core_stubs"


def reexports(tree: ast.Module) -> dict[str, list[str]]:
    """Names the stub re-exports (``import X as X``), by the piece they come from."""
    out: dict[str, list[str]] = {}
    for node in tree.body:
        if isinstance(node, ast.ImportFrom) and node.level == 1 and (node.module or "").startswith("_core_stubs."):
            piece = node.module.removeprefix("_core_stubs.")
            out.setdefault(piece, []).extend(a.name for a in node.names if a.asname == a.name)
    return out


REEXPORTS = reexports(STUB)
PIECE_TREES = {
    path.name.removesuffix(".pyi"): ast.parse(path.read_text(encoding="utf-8"))
    for path in PIECES.iterdir()
    if path.name.endswith(".pyi") and path.name != "__init__.pyi"
}


def defined_name(node: ast.stmt) -> str | None:
    if isinstance(node, (ast.FunctionDef, ast.ClassDef)):
        return node.name
    if isinstance(node, ast.AnnAssign) and isinstance(node.target, ast.Name):
        return node.target.id
    return None


# What `import neurov._core` gives a type checker: the stub's own statements
# and the re-exported ones, as one module body.
MODULE_BODY = [n for n in STUB.body if defined_name(n)] + [
    node
    for piece, names in REEXPORTS.items()
    for node in PIECE_TREES[piece].body
    if defined_name(node) in names
]


def public(name: str) -> bool:
    return not name.startswith("_") or name in ("__version__", "__init__")


def split_top_level(text: str) -> list[str]:
    parts, depth, current = [], 0, ""
    for ch in text:
        if ch in "([{":
            depth += 1
        elif ch in ")]}":
            depth -= 1
        if ch == "," and depth == 0:
            parts.append(current.strip())
            current = ""
        else:
            current += ch
    if current.strip():
        parts.append(current.strip())
    return parts


def parse_signature(params: str) -> list[str]:
    """pybind11's 'a: object, b: neurov._core.Vehicle, *, c: object = 1' as
    ['a', 'b: Vehicle', '*', 'c=1'] (self and '/' dropped)."""
    out = []
    for part in split_top_level(params):
        if part == "/":
            continue
        name, _, rest = part.partition(":")
        name = name.strip()
        if name == "self":
            continue
        annotation, _, default = rest.partition(" = ")
        annotation = annotation.strip()
        if annotation.startswith("neurov._core."):
            name = f"{name}: {annotation.removeprefix('neurov._core.')}"
        out.append(f"{name}={default.strip()}" if default else name)
    return out


def runtime_signatures(obj: Any) -> list[list[str]]:
    """One parameter list per pybind11 overload, from the docstring."""
    if inspect.isfunction(obj):
        # Attached in Python (Vehicle.from_file reads files, the package's work).
        return [[p.name for p in inspect.signature(obj).parameters.values() if p.name != "self"]]
    doc = obj.__doc__ or ""
    name = obj.__name__
    if "Overloaded function." in doc:
        found = re.findall(rf"^\d+\. {name}\((.*?)\) ->", doc, flags=re.M)
    else:
        found = re.findall(rf"^{name}\((.*?)\) ->", doc.lstrip(), flags=re.M)[:1]
    assert found, f"no pybind11 signature in {doc[:80]!r}"
    return [parse_signature(p) for p in found]


STUB_CLASSES = {
    n.name: n for tree in [STUB, *PIECE_TREES.values()] for n in tree.body if isinstance(n, ast.ClassDef)
}


def field_aliases() -> dict[str, bool]:
    """The descriptor types a field is annotated with, and whether each has a setter:
    ``_Field`` itself and the core piece's aliases of it (``_ReadOnly = _Field[_G, Never]``)."""
    out = {}
    for node in PIECE_TREES["core"].body:
        if (
            isinstance(node, ast.Assign)
            and isinstance(node.value, ast.Subscript)
            and ast.unparse(node.value.value) == "_Field"
        ):
            out[ast.unparse(node.targets[0])] = has_setter(node.value)
    return out


def has_setter(annotation: ast.Subscript) -> bool:
    """Whether ``_Field[get, set]`` takes a value: not when set is Never."""
    args = annotation.slice
    assert isinstance(args, ast.Tuple) and len(args.elts) == 2, ast.unparse(annotation)
    return ast.unparse(args.elts[1]) != "Never"


class Field(NamedTuple):
    """A property written as a descriptor-annotated class attribute."""

    writable: bool
    doc: str | None


def stub_parameters(node: ast.FunctionDef) -> list[str]:
    def one(arg: ast.arg, default: ast.expr | None) -> str:
        text = arg.arg
        if isinstance(arg.annotation, ast.Name) and arg.annotation.id in STUB_CLASSES:
            text += f": {arg.annotation.id}"
        return text if default is None else f"{text}={ast.unparse(default)}"

    a = node.args
    positional = a.posonlyargs + a.args
    defaults: list[ast.expr | None] = [None] * (len(positional) - len(a.defaults))
    defaults += a.defaults
    out = [one(arg, d) for arg, d in zip(positional, defaults) if arg.arg != "self"]
    if a.vararg:
        out.append(f"*{a.vararg.arg}")
    elif a.kwonlyargs:
        out.append("*")
    out += [one(arg, d) for arg, d in zip(a.kwonlyargs, a.kw_defaults)]
    if a.kwarg:
        out.append(f"**{a.kwarg.arg}")
    return out


def decorators(node: ast.FunctionDef) -> set[str]:
    return {ast.unparse(d) for d in node.decorator_list}


def functions_of(body: list[ast.stmt]) -> dict[str, list[ast.FunctionDef]]:
    out: dict[str, list[ast.FunctionDef]] = {}
    for node in body:
        if isinstance(node, ast.FunctionDef):
            out.setdefault(node.name, []).append(node)
    return out


FIELD_ALIASES = field_aliases()


def fields_of(body: list[ast.stmt]) -> dict[str, Field]:
    """Class attributes annotated with _Field or an alias of it, with the docstring below each."""
    out = {}
    for node, after in zip(body, [*body[1:], None]):
        if not (isinstance(node, ast.AnnAssign) and isinstance(node.target, ast.Name)):
            continue
        annotation = node.annotation
        root = annotation.value if isinstance(annotation, ast.Subscript) else annotation
        if not isinstance(root, ast.Name) or root.id not in {"_Field", *FIELD_ALIASES}:
            continue
        if root.id == "_Field":
            assert isinstance(annotation, ast.Subscript)
            writable = has_setter(annotation)
        else:
            writable = FIELD_ALIASES[root.id]
        doc = after.value.value if isinstance(after, ast.Expr) and isinstance(after.value, ast.Constant) else None
        out[node.target.id] = Field(writable, doc if isinstance(doc, str) else None)
    return out


def class_members(name: str) -> dict[str, list[ast.FunctionDef] | Field]:
    """Methods and fields of a stub class including those of its stub-only bases."""
    cls = STUB_CLASSES[name]
    out: dict[str, list[ast.FunctionDef] | Field] = {}
    for base in cls.bases:
        if isinstance(base, ast.Name) and base.id in STUB_CLASSES:
            out.update(class_members(base.id))
    out.update(functions_of(cls.body))
    out.update(fields_of(cls.body))
    return out


def class_variables(name: str) -> set[str]:
    """Names a stub class (or a stub-only base of it) declares ``ClassVar``: plain
    class attributes such as a controller's ``type_name``, not properties."""
    cls = STUB_CLASSES[name]
    out = {n for base in cls.bases if isinstance(base, ast.Name) and base.id in STUB_CLASSES
           for n in class_variables(base.id)}
    for node in cls.body:
        if (isinstance(node, ast.AnnAssign) and isinstance(node.target, ast.Name)
                and isinstance(node.annotation, ast.Subscript)
                and isinstance(node.annotation.value, ast.Name) and node.annotation.value.id == "ClassVar"):
            out.add(node.target.id)
    return out


def module_names() -> set[str]:
    return {name for node in MODULE_BODY if (name := defined_name(node))}


RUNTIME_FUNCTIONS = sorted(n for n in dir(core) if public(n) and inspect.isroutine(getattr(core, n)))
RUNTIME_CLASSES = sorted(n for n in dir(core) if public(n) and inspect.isclass(getattr(core, n)))


def test_stub_and_marker_are_installed() -> None:
    assert STUB_FILE.is_file()
    assert (importlib.resources.files("neurov") / "py.typed").is_file()
    assert (PIECES / "__init__.pyi").is_file()
    assert set(PIECE_TREES) == {"core", "model", "control", "sim"}


@pytest.mark.parametrize("piece", ["core", "model", "control", "sim"])
def test_pieces_are_stub_only_and_each_name_stands_once(piece: str) -> None:
    assert "for type checkers" in (ast.get_docstring(PIECE_TREES[piece]) or ""), piece
    names = [defined_name(n) for n in PIECE_TREES[piece].body if defined_name(n)]
    others = {defined_name(n) for p, t in PIECE_TREES.items() if p != piece for n in t.body}
    assert not (set(names) & others), "a name defined in two pieces"
    assert set(REEXPORTS.get(piece, [])) <= set(names), "a re-export of a name the piece does not define"


def test_module_names_match() -> None:
    assert {n for n in module_names() if public(n)} == {n for n in dir(core) if public(n)}


def test_constants() -> None:
    assert isinstance(core.__version__, str) and core.__version__
    assert isinstance(core.THETA_NAMES, tuple) and all(isinstance(n, str) for n in core.THETA_NAMES)


@pytest.mark.parametrize("name", RUNTIME_FUNCTIONS)
def test_function_parameters_match(name: str) -> None:
    stub = functions_of(MODULE_BODY)[name]
    runtime = runtime_signatures(getattr(core, name))
    if len(runtime) > 1:
        stub = [f for f in stub if "overload" in decorators(f)]
    assert [stub_parameters(f) for f in stub] == runtime
    assert ast.get_docstring(stub[0]), f"{name} has no docstring in the stub"


@pytest.mark.parametrize("cls_name", RUNTIME_CLASSES)
def test_class_members_match(cls_name: str) -> None:
    cls = getattr(core, cls_name)
    members = class_members(cls_name)
    if hasattr(cls, "__members__"):  # an enum: its members are values, not members to match
        runtime = {n for n in vars(cls) if public(n) and not isinstance(vars(cls)[n], cls)}
        assert {n for n in members if public(n)} == runtime
    else:
        assert {n for n in members if public(n)} | class_variables(cls_name) == {n for n in vars(cls) if public(n)}
    for name, nodes in members.items():
        if not public(name):
            continue
        raw = inspect.getattr_static(cls, name)
        if isinstance(nodes, Field):
            assert isinstance(raw, property), f"{cls_name}.{name} is a field in the stub, not a property"
            assert nodes.doc, f"{cls_name}.{name} has no docstring in the stub"
            assert (raw.fset is not None) == nodes.writable, f"{cls_name}.{name} setter"
            continue
        kinds = decorators(nodes[0])
        assert isinstance(raw, staticmethod) == ("staticmethod" in kinds), name
        assert isinstance(raw, property) == ("property" in kinds), name
        assert ast.get_docstring(nodes[0]), f"{cls_name}.{name} has no docstring in the stub"
        if isinstance(raw, property):
            has_setter = any(f"{name}.setter" in decorators(n) for n in nodes)
            assert (raw.fset is not None) == has_setter, f"{cls_name}.{name} setter"
        else:
            assert [stub_parameters(n) for n in nodes] == runtime_signatures(getattr(cls, name)), name


def test_benchmark_helpers_are_not_in_the_core() -> None:
    """The timing helpers live in neurov._bench, built only with NEUROV_BUILD_BENCH."""
    assert not [n for n in dir(core) if n.startswith("_time")]


def test_robust_modification_members_match() -> None:
    assert set(core.RobustModification.__members__) == {"none", "sigma", "e_modification", "projection"}
    assert int(core.RobustModification.none) == 0


def test_status_members_match() -> None:
    members = {
        node.target.id
        for node in STUB_CLASSES["Status"].body
        if isinstance(node, ast.AnnAssign)
        and isinstance(node.target, ast.Name)
        and ast.unparse(node.annotation) == "ClassVar[Status]"
    }
    assert members == set(core.Status.__members__)
    assert {name: int(value) for name, value in core.Status.__members__.items()} == {
        "ok": 0,
        "near_singularity": 1,
        "non_finite_input": 2,
        "invalid_argument": 3,
        "non_finite_output": 4,
    }
    assert core.Status(2) == core.Status.non_finite_input
    assert core.Status.ok.name == "ok" and core.Status.near_singularity.value == 1


def typed_dict_keys(name: str) -> set[str]:
    return {
        node.target.id
        for node in STUB_CLASSES[name].body
        if isinstance(node, ast.AnnAssign) and isinstance(node.target, ast.Name)
    }


def test_vehicle_parameters_keys_match_the_stub() -> None:
    assert typed_dict_keys("_VehicleParameters") == set(core.Vehicle.nerov().parameters())


def test_tracking_keys_match_the_stub() -> None:
    z = [0.0] * 6
    assert typed_dict_keys("_Tracking") == set(core.tracking_error(z, z, z, z, z, [1.0] * 6))


def test_simulation_result_keys_match_the_stub() -> None:
    config = core.SimulationConfig(duration=0.4, command=core.Command(times=[0.0], poses=[[0.0] * 6]))
    result = core.run_closed_loop(core.Vehicle.nerov(), core.PDController([1.0] * 6, [1.0] * 6), config)
    assert typed_dict_keys("_SimulationResult") == set(result)
    simulator = core.Simulator(core.Vehicle.nerov(), config)
    assert typed_dict_keys("_SimulationResult") == set(simulator.result())


@pytest.mark.parametrize("enum", ["SensorFaultKind", "RefusedStepPolicy", "Saturation"])
def test_enum_members_match(enum: str) -> None:
    members = {
        node.target.id
        for node in STUB_CLASSES[enum].body
        if isinstance(node, ast.AnnAssign) and ast.unparse(node.annotation) == f"ClassVar[{enum}]"
    }
    assert members == set(getattr(core, enum).__members__)


# A user's script: mypy must report an error on exactly the lines marked
# "error" (what the compiled module refuses or a wrong use of what it returns).
USER_SCRIPT = """\
import numpy as np
import numpy.typing as npt
from typing_extensions import assert_type

from neurov._core import PDConfig, PIDConfig, RbfNetwork, SimulationConfig, ThrusterFailure, Vehicle

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
