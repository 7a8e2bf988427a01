"""The package's house rules, read from the source (docs/architecture.md,
"Import rules"):

1. No import cycle between neurov's modules. Every module's AST is read,
   function-local imports included and ``if TYPE_CHECKING:`` blocks excluded
   (they never run). An edge ``import a.b`` goes to ``a.b``; an edge
   ``from a.b import c`` goes to module ``a.b.c`` if that is a module, else
   to ``a.b``; relative imports are resolved first. The implicit import of a
   module's parent packages is not an edge, and a package's own
   ``__init__`` importing its descendants is not one either (a package
   gathers its children); anything else is. A cycle is reported as a path.
   The imports of ``if TYPE_CHECKING:`` blocks may not close a cycle
   either: a type imported for annotations only that ties two modules
   together is a type in the wrong module (:func:`type_cycles`).
2. No private name (``_x``, dunders aside) imported across modules, nor read
   as an attribute of an imported neurov module; the compiled modules
   ``neurov._core`` and ``neurov._bench`` are the exception.
3. No two modules (files or packages anywhere in neurov) whose names differ
   only by a suffix or a plural: after dropping a plural ``s``/``es`` and one
   of the suffixes ``-er``, ``-or``, ``-ler``, ``-ion``, ``-ation``, or an
   ``_anything`` tail, no two names may meet (``controller``/``controls``/
   ``control``, ``simulation``/``simulator``, ``run``/``run_stream`` would).
   The same name in two packages (``study.spec``, ``tuning.spec``) is a
   parallel, not a near-synonym, and is allowed.
4. No import runs up the layers of :data:`LAYERS` (docs/architecture.md's
   table, in the same order): a module imports only modules of its own
   layer or of the layers before it, function-local imports included and
   ``if TYPE_CHECKING:`` blocks excluded. What a bridge lends to a layer
   beneath it goes through ``neurov.hooks`` (registered by
   ``neurov.bridges``, on top).
5. ``import neurov`` stays cheap: test_import_cost.py.
6. Small files: test_file_sizes.py.
7. One "did you mean": :func:`neurov.schema.did_you_mean` is the only user
   of :mod:`difflib`; every reader's suggestion comes from it.

Run as a script, this file prints the counts docs/architecture.md quotes:
``python tests/python/test_package_layout.py python/neurov``.
"""

from __future__ import annotations

import ast
import itertools
import sys
from dataclasses import dataclass, field
from pathlib import Path

import pytest

PACKAGE = Path(__file__).resolve().parents[2] / "python" / "neurov"
# The compiled modules and the generated stub that re-exports the core's
# controllers for type checkers (tools/generate_stubs.py).
COMPILED = ("neurov._core", "neurov._bench", "neurov._core_controllers")
PLURALS = ("es", "s")
SUFFIXES = ("ation", "ion", "ler", "er", "or")


LAYERS = (
    ("foundations", ("neurov.errors", "neurov.files", "neurov.npz_file", "neurov.progress", "neurov.kernels",
                     "neurov.hooks", "neurov.schema", "neurov.units", "neurov.threads", "neurov.memory")),
    ("control laws", ("neurov.laws",)),
    ("configuration", ("neurov.config",)),
    ("results", ("neurov.results",)),
    ("running", ("neurov.running",)),
    ("bridges", ("neurov.control", "neurov.recording", "neurov.replay")),
    ("on top", ("neurov",)),
)
"""The layers, first to last, each as the module names (and the packages'
names, for every module beneath them) it holds; a module belongs to the
longest name that is its own or a package of it (so ``neurov`` itself and
everything not named before, ``cli``, ``gym``, ``study``, ``tuning``, ...,
are on top)."""


@dataclass
class Module:
    name: str
    path: Path
    is_package: bool
    tree: ast.Module


@dataclass
class Import:
    source: str
    target: str
    line: int
    local: bool  # inside a function
    names: list[str] = field(default_factory=list)
    typed: bool = False  # inside an ``if TYPE_CHECKING:`` block: never run


def modules(root: Path = PACKAGE) -> dict[str, Module]:
    """Every module of the package under `root`, by dotted name."""
    found = {}
    for path in sorted(root.rglob("*.py")):
        parts = path.relative_to(root.parent).with_suffix("").parts
        is_package = parts[-1] == "__init__"
        name = ".".join(parts[:-1] if is_package else parts)
        found[name] = Module(name, path, is_package, ast.parse(path.read_text(encoding="utf-8"), str(path)))
    return found


def _is_type_checking(test: ast.expr) -> bool:
    return (isinstance(test, ast.Name) and test.id == "TYPE_CHECKING") or (
        isinstance(test, ast.Attribute) and test.attr == "TYPE_CHECKING")


def _import_nodes(node: ast.AST, local: bool = False, typed: bool = False):
    """(node, in a function, in an ``if TYPE_CHECKING:`` block) for every
    import statement."""
    for child in ast.iter_child_nodes(node):
        if isinstance(child, ast.If) and _is_type_checking(child.test):
            for body, inner_typed in ((child.body, True), (child.orelse, typed)):
                for other in body:
                    yield from _import_nodes(ast.Module(body=[other], type_ignores=[]), local, inner_typed)
            continue
        if isinstance(child, (ast.Import, ast.ImportFrom)):
            yield child, local, typed
        inner = local or isinstance(child, (ast.FunctionDef, ast.AsyncFunctionDef, ast.Lambda))
        yield from _import_nodes(child, inner, typed)


def _absolute(module: Module, node: ast.ImportFrom) -> str:
    if not node.level:
        return node.module or ""
    base = module.name.split(".")
    if not module.is_package:
        base = base[:-1]
    base = base[: len(base) - (node.level - 1)]
    return ".".join(base + ([node.module] if node.module else []))


def imports(found: dict[str, Module], typed: bool = False) -> list[Import]:
    """The edges between neurov's modules (see the module's docstring); with
    `typed`, those of ``if TYPE_CHECKING:`` blocks too."""
    edges = []
    for module in found.values():
        for node, local, in_block in _import_nodes(module.tree):
            if in_block and not typed:
                continue
            if isinstance(node, ast.Import):
                targets = [(alias.name, []) for alias in node.names]
            else:
                base = _absolute(module, node)
                targets = []
                for alias in node.names:
                    sub = f"{base}.{alias.name}"
                    targets.append((sub, []) if sub in found or sub in COMPILED else (base, [alias.name]))
            for target, names in targets:
                if target.split(".")[0] != "neurov":
                    continue
                edges.append(Import(module.name, target, node.lineno, local, names, in_block))
    return edges


def graph(found: dict[str, Module], typed: bool = False, children: bool = False) -> dict[str, set[str]]:
    """Module -> the neurov modules it imports: with `typed`, those of ``if
    TYPE_CHECKING:`` blocks too; with `children`, a package's own children
    too (left out by rule 1, but a type imported from a package brings
    every import of its ``__init__``)."""
    out: dict[str, set[str]] = {name: set() for name in found}
    for edge in imports(found, typed):
        if edge.target not in found or edge.target == edge.source:
            continue
        if found[edge.source].is_package and edge.target.startswith(edge.source + ".") and not children:
            continue
        out[edge.source].add(edge.target)
    return out


def cycles(found: dict[str, Module], typed: bool = False,
           edges: dict[str, set[str]] | None = None) -> list[list[str]]:
    """One cycle (as a path, its first module repeated at its end) per
    strongly connected group of modules (Tarjan's algorithm) of `edges`,
    default :func:`graph`'s (with `typed`, see there)."""
    edges = graph(found, typed) if edges is None else edges
    index: dict[str, int] = {}
    low: dict[str, int] = {}
    stack: list[str] = []
    on_stack: set[str] = set()
    groups: list[list[str]] = []

    def visit(v: str) -> None:
        index[v] = low[v] = len(index)
        stack.append(v)
        on_stack.add(v)
        for w in sorted(edges[v]):
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on_stack:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            group = []
            while True:
                w = stack.pop()
                on_stack.discard(w)
                group.append(w)
                if w == v:
                    break
            if len(group) > 1:
                groups.append(sorted(group))

    sys.setrecursionlimit(max(sys.getrecursionlimit(), 10 * len(edges)))
    for v in sorted(edges):
        if v not in index:
            visit(v)
    return [_path_in(group, edges) for group in sorted(groups)]


def cyclic_groups(found: dict[str, Module], typed: bool = False,
                  edges: dict[str, set[str]] | None = None) -> list[list[str]]:
    """The modules that import each other, directly or not, group by group."""
    edges = graph(found, typed) if edges is None else edges
    paths = cycles(found, edges=edges)
    reach = {}
    for v in edges:
        seen, todo = set(), [v]
        while todo:
            for w in edges[todo.pop()]:
                if w not in seen:
                    seen.add(w)
                    todo.append(w)
        reach[v] = seen
    return [sorted(v for v in edges if v in reach[p[0]] and p[0] in reach[v]) for p in paths]


def _path_in(group: list[str], edges: dict[str, set[str]]) -> list[str]:
    """A shortest cycle through the group's first module (breadth first)."""
    start, members = group[0], set(group)
    previous = {start: None}
    queue = [start]
    for v in queue:
        for w in sorted(edges[v] & members):
            if w == start:
                path = [v]
                while previous[path[-1]] is not None:
                    path.append(previous[path[-1]])
                return [start, *reversed(path[:-1]), start] if len(path) > 1 else [start, v, start]
            if w not in previous:
                previous[w] = v
                queue.append(w)
    raise AssertionError(f"no cycle through {start}")


def type_cycles(found: dict[str, Module]) -> list[list[str]]:
    """The cycles an ``if TYPE_CHECKING:`` import closes (rule 1): one path
    per group of modules that import each other with those imports and are
    not such a group without them (both counting a package's imports of its
    own children)."""
    typed = graph(found, typed=True, children=True)
    running = [set(group) for group in cyclic_groups(found, edges=graph(found, children=True))]
    return [path for path, group in zip(cycles(found, edges=typed), cyclic_groups(found, edges=typed))
            if set(group) not in running]


def difflib_users(found: dict[str, Module]) -> list[str]:
    """The modules that import difflib, the one did-you-mean's aside (rule 7)."""
    users = set()
    for module in found.values():
        for node in ast.walk(module.tree):
            names = ([a.name for a in node.names] if isinstance(node, ast.Import) else
                     [node.module or ""] if isinstance(node, ast.ImportFrom) else [])
            if any(name.split(".")[0] == "difflib" for name in names):
                users.add(module.name)
    return sorted(users - {"neurov.schema"})


def local_imports(found: dict[str, Module]) -> list[Import]:
    """The imports of neurov modules written inside a function."""
    return [edge for edge in imports(found) if edge.local]


def _private(name: str) -> bool:
    return name.startswith("_") and not (name.startswith("__") and name.endswith("__"))


def private_imports(found: dict[str, Module]) -> list[str]:
    """Where a module takes another's private name (rule 2)."""
    bad = []
    for module in found.values():
        aliases: dict[str, str] = {}
        for node in ast.walk(module.tree):  # TYPE_CHECKING blocks included: a private name is private there too
            if isinstance(node, ast.Import):
                for alias in node.names:
                    if alias.asname:
                        aliases[alias.asname] = alias.name
            elif isinstance(node, ast.ImportFrom):
                base = _absolute(module, node)
                if base.split(".")[0] != "neurov":
                    continue
                for alias in node.names:
                    target = f"{base}.{alias.name}"
                    if target in COMPILED:
                        continue
                    if target in found:
                        aliases[alias.asname or alias.name] = target
                    elif _private(alias.name) and base not in COMPILED:
                        bad.append(f"{module.name}:{node.lineno} imports {alias.name} from {base}")
                parts = base.split(".")
                if any(_private(p) for p in parts) and base not in COMPILED:
                    bad.append(f"{module.name}:{node.lineno} imports the private module {base}")
        for node in ast.walk(module.tree):
            if (isinstance(node, ast.Attribute) and isinstance(node.value, ast.Name) and _private(node.attr)
                    and aliases.get(node.value.id) in found):
                bad.append(f"{module.name}:{node.lineno} reads {node.value.id}.{node.attr}")
    return bad


def _stems(name: str) -> set[str]:
    stems = {name}
    for plural in PLURALS:
        if name.endswith(plural) and len(name) > len(plural) + 2:
            stems.add(name[: -len(plural)])
    for stem in list(stems):
        for suffix in SUFFIXES:
            if stem.endswith(suffix) and len(stem) > len(suffix) + 2:
                stems.add(stem[: -len(suffix)])
    return stems


def near_synonyms(found: dict[str, Module]) -> list[tuple[str, str]]:
    """Pairs of modules whose last names differ only by a suffix or a plural (rule 3)."""
    by_name: dict[str, list[str]] = {}
    for name in found:
        if "." not in name:
            continue  # the package itself
        last = name.rsplit(".", 1)[-1]
        if not (last.startswith("__") and last.endswith("__")):
            by_name.setdefault(last, []).append(name)
    pairs = []
    for a, b in itertools.combinations(sorted(by_name), 2):
        if _stems(a) & _stems(b) or a.startswith(b + "_") or b.startswith(a + "_"):
            pairs.append((by_name[a][0], by_name[b][0]))
    return pairs


def layer_of(name: str) -> int:
    """The index in :data:`LAYERS` of module `name`."""
    best, length = len(LAYERS) - 1, 0
    for i, (_, names) in enumerate(LAYERS):
        for prefix in names:
            if (name == prefix or name.startswith(prefix + ".")) and len(prefix) > length:
                best, length = i, len(prefix)
    return best


def imports_up(found: dict[str, Module]) -> list[str]:
    """Every import of a module of a later layer (rule 4), as
    ``source:line imports target (layer -> layer)``."""
    bad = []
    for edge in imports(found):
        if edge.target not in found:
            continue
        a, b = layer_of(edge.source), layer_of(edge.target)
        if b > a:
            where = " in a function" if edge.local else ""
            bad.append(f"{edge.source}:{edge.line} imports {edge.target}{where} "
                       f"({LAYERS[a][0]} -> {LAYERS[b][0]})")
    return sorted(set(bad))


FOUND = modules()


def test_no_import_cycle() -> None:
    found = cycles(FOUND)
    assert not found, "import cycles: " + "; ".join(" -> ".join(path) for path in found)


TYPE_CYCLES_LEFT = {
    ("neurov.config.scenario", "neurov.laws.registry"),
    ("neurov.identification.fit", "neurov.identification.report"),
    ("neurov.results.metrics", "neurov.results.timeseries"),
}
"""The circles through a type-only import still to be undone (issue #39:
each moves a type to the module it belongs in); the test fails when one is
gone, so that it leaves this list, and when a new one comes."""


def test_no_import_cycle_through_a_type_only_import() -> None:
    found = {tuple(sorted(set(path))) for path in type_cycles(FOUND)}
    assert found <= TYPE_CYCLES_LEFT, "import cycles through a TYPE_CHECKING import: " + "; ".join(
        " -> ".join(path) for path in type_cycles(FOUND) if tuple(sorted(set(path))) not in TYPE_CYCLES_LEFT)
    assert found >= TYPE_CYCLES_LEFT, f"undone, to take out of TYPE_CYCLES_LEFT: {sorted(TYPE_CYCLES_LEFT - found)}"


def test_one_did_you_mean() -> None:
    assert not difflib_users(FOUND), f"difflib used besides neurov.schema.did_you_mean: {difflib_users(FOUND)}"


def test_no_private_name_crosses_a_module() -> None:
    assert not private_imports(FOUND), "\n".join(private_imports(FOUND))


def test_no_import_runs_up_the_layers() -> None:
    assert not imports_up(FOUND), "\n".join(imports_up(FOUND))


def test_no_two_module_names_differ_only_by_a_suffix() -> None:
    assert not near_synonyms(FOUND), near_synonyms(FOUND)


def test_the_rules_see_what_they_forbid(tmp_path: Path) -> None:
    """The checks above on a planted package: a cycle through a function-local
    import (and none through a TYPE_CHECKING one), a private name, two
    near-synonyms."""
    root = tmp_path / "neurov"
    (root / "running").mkdir(parents=True)
    (root / "__init__.py").write_text("from neurov.running import simulation\n")
    (root / "running" / "__init__.py").write_text("")
    (root / "running" / "simulation.py").write_text(
        "from neurov import simulator\n\ndef f():\n    from neurov.running.plant import _build\n")
    (root / "running" / "plant.py").write_text(
        "from typing import TYPE_CHECKING\nif TYPE_CHECKING:\n    from neurov import simulator\n"
        "    from neurov.results.table import Row\nelse:\n    import difflib\n"
        "def g():\n    from neurov.running import simulation\n")
    (root / "simulator.py").write_text("import neurov._core\n")
    (root / "results").mkdir()
    (root / "results" / "__init__.py").write_text("")
    (root / "results" / "table.py").write_text("def h():\n    from neurov.running import plant\n")
    planted = modules(root)
    assert cycles(planted) == [["neurov.running.plant", "neurov.running.simulation", "neurov.running.plant"]]
    # The TYPE_CHECKING import of Row closes results.table -> running.plant -> results.table; the one of
    # simulator closes none (simulator imports nothing of neurov's).
    assert type_cycles(planted) == [["neurov.results.table", "neurov.running.plant", "neurov.results.table"]]
    assert difflib_users(planted) == ["neurov.running.plant"]
    assert private_imports(planted) == ["neurov.running.simulation:4 imports _build from neurov.running.plant"]
    assert near_synonyms(planted) == [("neurov.running.simulation", "neurov.simulator")]
    assert {(e.source, e.target) for e in local_imports(planted)} == {
        ("neurov.running.simulation", "neurov.running.plant"), ("neurov.running.plant", "neurov.running.simulation"),
        ("neurov.results.table", "neurov.running.plant")}
    assert imports_up(planted) == [
        "neurov.results.table:2 imports neurov.running.plant in a function (results -> running)",
        "neurov.running.simulation:1 imports neurov.simulator (running -> on top)"]


@pytest.mark.parametrize("name, other", [("controller", "control"), ("controllers", "control"),
                                         ("simulation", "simulator"), ("run", "run_stream"),
                                         ("scenario", "scenario_file"), ("figure", "figures")])
def test_near_synonyms_named_in_the_issue_are_caught(name: str, other: str) -> None:
    assert _stems(name) & _stems(other) or name.startswith(other + "_") or other.startswith(name + "_")


if __name__ == "__main__":  # the counts quoted in docs/architecture.md
    found = modules(Path(sys.argv[1]).resolve() if len(sys.argv) > 1 else PACKAGE)
    local = local_imports(found)
    statements = {(e.source, e.line) for e in local}
    print(f"modules: {len(found)}")
    print(f"function-local import statements of neurov modules: {len(statements)} in "
          f"{len({e.source for e in local})} files")
    for path, group in zip(cycles(found), cyclic_groups(found)):
        print("cycle: " + " -> ".join(path) + f"  (a group of {len(group)}: {', '.join(group)})")
    print(f"import cycles (groups of modules that import each other): {len(cycles(found))}")
    for path in type_cycles(found):
        print("cycle through a TYPE_CHECKING import: " + " -> ".join(path))
    print(f"import cycles through a TYPE_CHECKING import: {len(type_cycles(found))}")
    for line in private_imports(found):
        print("private: " + line)
    for a, b in near_synonyms(found):
        print(f"near-synonyms: {a} / {b}")
    for line in imports_up(found):
        print("up: " + line)
    print(f"imports running up the layers: {len(imports_up(found))}")
