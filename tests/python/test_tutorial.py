"""docs/tutorial.md runs as written: its Python blocks, executed in order in
one namespace, print exactly the output shown under each of them."""

from __future__ import annotations

import contextlib
import io
import re
from pathlib import Path

import pytest

TUTORIAL = Path(__file__).resolve().parents[2] / "docs" / "tutorial.md"

# A fenced Python block, then (after blank lines) the indented output it
# prints, if any.
_BLOCK = re.compile(r"```python\n(?P<code>.*?)```\n(?:\n(?P<out>(?: {4}[^\n]*\n)+))?", re.S)


def _blocks() -> list[tuple[str, str]]:
    text = TUTORIAL.read_text(encoding="utf-8")
    found = [(m["code"], "".join(line[4:] + "\n" for line in (m["out"] or "").splitlines()))
             for m in _BLOCK.finditer(text)]
    assert found, f"no Python blocks in {TUTORIAL}"
    return found


def test_tutorial_prints_what_it_shows(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.chdir(tmp_path)  # the tutorial writes its figures to the working folder
    namespace: dict[str, object] = {}
    for i, (code, expected) in enumerate(_blocks()):
        out = io.StringIO()
        with contextlib.redirect_stdout(out):
            exec(compile(code, f"{TUTORIAL.name} block {i + 1}", "exec"), namespace)  # noqa: S102
        assert out.getvalue() == expected, f"block {i + 1} of {TUTORIAL.name}"
    assert sorted(p.name for p in tmp_path.glob("*.png")) == [
        "errors.png", "fig3_xy.png", "fig4_inputs.png", "fig5_yaw.png"]
