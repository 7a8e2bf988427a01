"""examples/tutorial.ipynb runs from top to bottom in a fresh Jupyter kernel
(nbclient), without an error or a warning, and draws its figures; and it is
kept in the repository with its outputs stripped."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

NOTEBOOK = Path(__file__).resolve().parents[2] / "examples" / "tutorial.ipynb"


def _code_cells(nb: dict) -> list[dict]:
    return [c for c in nb["cells"] if c["cell_type"] == "code"]


def test_notebook_is_stored_without_outputs() -> None:
    nb = json.loads(NOTEBOOK.read_text(encoding="utf-8"))
    cells = _code_cells(nb)
    assert cells, f"no code cells in {NOTEBOOK}"
    for i, cell in enumerate(cells):
        assert cell["outputs"] == [] and cell["execution_count"] is None, (
            f"code cell {i + 1} of {NOTEBOOK.name} keeps its outputs; clear them before committing")


def test_notebook_runs(tmp_path: Path) -> None:
    pytest.importorskip("control", minversion="0.10")
    nbformat = pytest.importorskip("nbformat")
    nbclient = pytest.importorskip("nbclient")

    nb = nbformat.read(NOTEBOOK, as_version=4)
    # Any error stops the run and fails here with the cell and its traceback.
    nbclient.NotebookClient(nb, timeout=300, kernel_name="python3",
                            resources={"metadata": {"path": str(tmp_path)}}).execute()

    cells = _code_cells(nb)
    stderr = [(i + 1, o["text"]) for i, c in enumerate(cells) for o in c["outputs"]
              if o["output_type"] == "stream" and o["name"] == "stderr"]
    assert not stderr, f"cells wrote to stderr (a warning?): {stderr}"
    # Every cell whose source draws a figure shows one.
    drawing = [i for i, c in enumerate(cells) if "plot." in c["source"] or ".plot(" in c["source"]]
    assert len(drawing) == 4
    for i in drawing:
        assert any("image/png" in o.get("data", {}) for o in cells[i]["outputs"]), (
            f"code cell {i + 1} draws no figure")
