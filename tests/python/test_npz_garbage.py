"""A file named .npz that is not a neurov result (random bytes, a single
.npy, Python objects) is named as such by every command that reads one;
never numpy's advice to "load it unsafely using allow_pickle" (which
``neurov identify`` gave for random bytes)."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

import neurov
from neurov.cli import main
from neurov.errors import ResultFileError


def _files(folder: Path) -> dict[str, Path]:
    rng = np.random.default_rng(38)
    (folder / "random.npz").write_bytes(rng.bytes(5000))
    with open(folder / "single.npz", "wb") as f:
        np.save(f, np.zeros(3))
    np.savez(folder / "objects.npz", t=np.array([object()] * 3), eta_estimate=np.zeros((3, 6)),
             nu_estimate=np.zeros((3, 6)), tau_applied=np.zeros((3, 6)))
    return {"random": folder / "random.npz", "single": folder / "single.npz", "objects": folder / "objects.npz"}


MESSAGES = {"random": r"random\.npz: not a \.npz archive \(BadZipFile: .*truncated, damaged or another kind of file\)",
            "single": r"single\.npz: a single \.npy array, not a \.npz archive",
            "objects": r"objects\.npz: array '\w+' holds Python objects .* never unpickled"}


@pytest.mark.parametrize("kind", sorted(MESSAGES))
def test_identify_names_a_file_that_is_no_result(tmp_path: Path, capsys: pytest.CaptureFixture[str],
                                                 kind: str) -> None:
    import re

    path = _files(tmp_path)[kind]
    assert main(["identify", str(path), "--vehicle", "nerov"]) == 1
    err = capsys.readouterr().err
    assert re.search(MESSAGES[kind], err), err
    assert "allow_pickle" not in err and "Traceback" not in err


def test_load_result_and_view_name_random_bytes(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    path = _files(tmp_path)["random"]
    with pytest.raises(ResultFileError, match=MESSAGES["random"]):
        neurov.load_result(path, scenario="paper_fig3")
    assert main(["view", str(path), "--out", str(tmp_path / "view.html")]) == 1
    err = capsys.readouterr().err
    assert "not a .npz archive" in err and "allow_pickle" not in err
