"""The identification package's modules import no cycle even through
``if TYPE_CHECKING:`` imports (test_package_layout.py's
``test_no_import_cycle_through_a_type_only_import`` holds the rule for the
whole package): a type two modules share lives below both. The fit and its
report once tied each other through the fit's result type
(``Identification``, then kept in the fit's module; now in ``outcome``)."""

from __future__ import annotations

from pathlib import Path

from import_graph import cycles, modules, type_cycles
from test_package_layout import FOUND


def test_identification_has_no_type_only_cycle() -> None:
    found = [path for path in type_cycles(FOUND) if any(m.startswith("neurov.identification.") for m in path)]
    assert not found, "type-only import cycles: " + "; ".join(" -> ".join(path) for path in found)


def test_a_type_only_cycle_is_seen(tmp_path: Path) -> None:
    root = tmp_path / "neurov"
    root.mkdir()
    (root / "__init__.py").write_text("")
    (root / "fit.py").write_text("from neurov.report import header\n")
    (root / "report.py").write_text("from typing import TYPE_CHECKING\nif TYPE_CHECKING:\n    from neurov.fit import Fit\n")
    planted = modules(root)
    assert cycles(planted) == []  # it never runs: rule 1 does not count it
    assert type_cycles(planted) == [["neurov.fit", "neurov.report", "neurov.fit"]]
