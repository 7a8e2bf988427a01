"""Sphinx configuration of the neurov documentation site.

Build (from the repository root, after ``pip install ".[docs]"`` and with
Doxygen on the PATH)::

    sphinx-build -W -b html docs docs/_build/html

The Python API pages are generated from the installed package's docstrings
(autosummary, recursive); the C++ API pages from the headers through Doxygen's
XML and Breathe. Doxygen runs here, before Sphinx reads the sources, so the
one command above builds everything.
"""

from __future__ import annotations

import re
import shutil
import subprocess
from pathlib import Path
from typing import Any

import neurov

DOCS = Path(__file__).resolve().parent
DOXYGEN_XML = DOCS / "_build" / "doxygen" / "xml"

project = "neurov"
author = "the neurov authors"
copyright = "the neurov authors"  # noqa: A001 (Sphinx's name)
release = neurov.__version__
version = release

extensions = [
    "myst_parser",
    "sphinx.ext.autodoc",
    "sphinx.ext.autosummary",
    "sphinx.ext.mathjax",
    # MathJax shipped with the site (_static/mathjax), not loaded from a CDN:
    # the equations render offline.
    "sphinx-mathjax-offline",
    "breathe",
]

source_suffix = {".rst": "restructuredtext", ".md": "markdown"}
root_doc = "index"
exclude_patterns = ["_build", "_templates", "Doxyfile", "data"]  # data: the committed outputs of long runs
templates_path = ["_templates"]

# Markdown: $...$ and $$...$$ math, and anchors for headings so the pages can
# link to each other's sections.
myst_enable_extensions = ["dollarmath"]
myst_heading_anchors = 3

# Python API: one page per module, generated at build time into api/generated.
autosummary_generate = True
autosummary_imported_members = False
autodoc_default_options = {"members": True, "show-inheritance": True}
autodoc_member_order = "bysource"
# The Stable-Baselines3 adapter's optional dependency (with PyTorch), not
# installed to build the docs: its page is written against a stand-in.
autodoc_mock_imports = ["stable_baselines3"]
autodoc_typehints = "description"
autodoc_typehints_description_target = "documented"
# No napoleon: the docstrings are prose, not NumPy or Google sections, and
# napoleon reads a colon in an attribute's first line ("... [s]: the weights")
# as "type: description".

# C++ API.
breathe_projects = {"neurov": str(DOXYGEN_XML)}
breathe_default_project = "neurov"
breathe_default_members = ("members",)
primary_domain = "py"

html_theme = "furo"
html_title = f"neurov {release}"
html_static_path: list[str] = []


def _run_doxygen() -> None:
    doxygen = shutil.which("doxygen")
    if doxygen is None:
        raise RuntimeError(
            "doxygen not found: the C++ API pages need it (Debian: apt-get install doxygen)"
        )
    DOXYGEN_XML.parent.mkdir(parents=True, exist_ok=True)
    subprocess.run([doxygen, "Doxyfile"], cwd=DOCS, check=True)


# The compiled module's docstrings are plain text written in C++ (pybind11):
# "|nu|" is an absolute value and "**kwargs" a Python signature, not
# reStructuredText substitutions or bold. They are escaped here rather than in
# the bindings, so that every docstring the core gains renders as written.
_RST_INLINE = re.compile(r"([*|`\\])|(?<=\w)_(?=\W|$)")


def _escape_core_docstring(
    app: Any, what: str, name: str, obj: Any, options: Any, lines: list[str]
) -> None:
    if name == "neurov._core" or name.startswith("neurov._core."):
        lines[:] = [_RST_INLINE.sub(lambda m: "\\" + m.group(0), line) for line in lines]


def setup(app: Any) -> None:
    app.connect("autodoc-process-docstring", _escape_core_docstring)


def _write_result_series() -> None:
    """The result's columns (docs/running.md includes them), from the C++ table."""
    from neurov.results.columns import markdown_table

    generated = DOCS / "_build" / "generated"
    generated.mkdir(parents=True, exist_ok=True)
    (generated / "result_series.md").write_text(markdown_table(), encoding="utf-8")


_run_doxygen()
_write_result_series()
