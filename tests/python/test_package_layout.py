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
   layer or of the layers before it, function-local imports included, and
   ``if TYPE_CHECKING:`` blocks too (checked apart). What a bridge lends to a layer
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
from pathlib import Path

import pytest

from import_graph import (COMPILED, PACKAGE, Module, absolute, cycles, cyclic_groups, imports, local_imports, modules,
                          type_cycles)

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
                base = absolute(module, node)
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


def imports_up(found: dict[str, Module], typed: bool = False) -> list[str]:
    """Every import of a module of a later layer (rule 4), as
    ``source:line imports target (layer -> layer)``; with `typed`, those of
    ``if TYPE_CHECKING:`` blocks instead."""
    bad = []
    for edge in imports(found, typed):
        if edge.target not in found or edge.typed != typed:
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


TYPE_CYCLES_LEFT: set[tuple[str, ...]] = set()
"""The circles through a type-only import still to be undone (issue #39
moved the last types to the modules they belong in): the test fails when
one is gone, so that it leaves this list, and when a new one comes."""


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


def test_no_type_only_import_runs_up_the_layers() -> None:
    """A type a lower layer needs from a higher one is a protocol of its own
    (``laws.registry.ScenarioLike``), not the higher layer's class."""
    assert not imports_up(FOUND, typed=True), "\n".join(imports_up(FOUND, typed=True))


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
    assert imports_up(planted, typed=True) == ["neurov.running.plant:3 imports neurov.simulator (running -> on top)"]
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
    for line in imports_up(found, typed=True):
        print("up (TYPE_CHECKING): " + line)
    print(f"TYPE_CHECKING imports running up the layers: {len(imports_up(found, typed=True))}")
