"""The import graph of neurov's modules, read from the source: the edges
test_package_layout.py checks (its rule 1 says which imports are edges),
the cycles, and the cycles a ``TYPE_CHECKING`` import closes."""

from __future__ import annotations

import ast
import sys
from dataclasses import dataclass, field
from pathlib import Path

PACKAGE = Path(__file__).resolve().parents[2] / "python" / "neurov"
# The compiled modules and the generated stub that re-exports the core's
# controllers for type checkers (tools/generate_stubs.py).
COMPILED = ("neurov._core", "neurov._bench", "neurov._core_controllers")


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


def absolute(module: Module, node: ast.ImportFrom) -> str:
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
                base = absolute(module, node)
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


def local_imports(found: dict[str, Module]) -> list[Import]:
    """The imports of neurov modules written inside a function."""
    return [edge for edge in imports(found) if edge.local]
