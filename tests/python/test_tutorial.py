"""docs/tutorial.md and docs/control.md run as written: each page's Python
blocks, executed in order in one namespace, print exactly the output shown
under each of them."""

from __future__ import annotations

import contextlib
import io
import re
from pathlib import Path

import pytest

DOCS = Path(__file__).resolve().parents[2] / "docs"

# A fenced Python block, then (after blank lines) the indented output it
# prints, if any.
_BLOCK = re.compile(r"```python\n(?P<code>.*?)```\n(?:\n(?P<out>(?: {4}[^\n]*\n)+))?", re.S)

# Per page, the figures its code writes to the working folder.
PAGES = {
    "tutorial.md": ["errors.png", "fig3_xy.png", "fig4_inputs.png", "fig5_yaw.png"],
    "control.md": [],
}


def _blocks(page: Path) -> list[tuple[str, str]]:
    text = page.read_text(encoding="utf-8")
    found = [(m["code"], "".join(line[4:] + "\n" for line in (m["out"] or "").splitlines()))
             for m in _BLOCK.finditer(text)]
    assert found, f"no Python blocks in {page}"
    return found


@pytest.mark.parametrize("name", sorted(PAGES))
def test_page_prints_what_it_shows(name: str, tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    if name == "control.md":
        pytest.importorskip("control", minversion="0.10")
    page = DOCS / name
    monkeypatch.chdir(tmp_path)  # a page writes its figures to the working folder
    namespace: dict[str, object] = {}
    for i, (code, expected) in enumerate(_blocks(page)):
        out = io.StringIO()
        with contextlib.redirect_stdout(out):
            exec(compile(code, f"{name} block {i + 1}", "exec"), namespace)  # noqa: S102
        assert out.getvalue() == expected, f"block {i + 1} of {name}"
    assert sorted(p.name for p in tmp_path.glob("*.png")) == PAGES[name]
