"""The command ``neurov view``: the 3-D replay of runs read back
(:func:`neurov.load_result`) from their folders or files (``neurov view RESULT [RESULT ...] --out replay.html``; see
:mod:`neurov.replay`)."""

from __future__ import annotations

import sys
import warnings
from collections.abc import Sequence
from pathlib import Path

from neurov.errors import NeurovError, ResultFileError
from neurov.replay import MAX_FRAMES, replay
from neurov.replay.scene import AbsurdValuesWarning
from neurov.results.load import load_result

__all__ = ["main_view"]


def _check_out(out: str) -> Path:
    """The --out file, checked before anything is read: not a folder, in a
    folder that exists."""
    path = Path(out)
    if path.is_dir():
        raise ResultFileError(f"--out {out!r}: is a folder; expected the HTML file to write (e.g. replay.html)")
    if not path.parent.is_dir():
        raise ResultFileError(f"--out {out!r}: the folder {str(path.parent)!r} does not exist")
    return path


def _name(path: Path) -> str:
    """What tells a run apart when two share a controller: its folder's name."""
    folder = path if path.is_dir() else path.parent
    return folder.resolve().name or str(path)


def main_view(results: Sequence[str], out: str, frames: int | None = None,
              scenario: str | None = None) -> int:
    """Reads each RESULT back (:func:`neurov.load_result`: a run folder or a
    result file, its scenario the one beside it unless `scenario` names
    one), writes the replay to `out`; returns the exit status (1 without
    plotly). A RESULT that cannot be read is named and nothing is written."""
    path = _check_out(out)
    runs = []
    for r in results:
        try:
            runs.append(load_result(r, scenario))
        except NeurovError as e:
            said = str(e)
            said = said.removeprefix(f"{r}: ").removeprefix(f"{Path(r)}: ")  # the path once, as given
            raise ResultFileError(f"RESULT {r!r}: {said}") from None
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", AbsurdValuesWarning)  # said below, once, as the command's warnings
            view = replay(runs, names=[_name(Path(r)) for r in results],
                          max_frames=MAX_FRAMES if frames is None else frames)
    except ImportError as e:  # plotly missing: the message says which extra to install
        print(f"neurov: error: {e}", file=sys.stderr)
        return 1
    for note in view.scene.notes:
        print(f"neurov: warning: {note}", file=sys.stderr)
    written = view.write_html(path)
    size = written.stat().st_size
    print(f"wrote {written} ({size / 1e6:.1f} MB, {len(view.scene.times)} frames, "
          f"{len(runs)} run{'s' if len(runs) > 1 else ''})")
    return 0
