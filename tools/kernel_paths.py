"""A study's runs.csv on each kernel path of the RBF loops that this CPU
runs, against the committed one (docs/studies.md, "Reproducibility").

    python tools/kernel_paths.py docs/data/robustness
    python tools/kernel_paths.py docs/data/robustness --paths generic --workers 1

Runs the study that wrote DIR (its ``study.json`` names the file) once per
``NEUROV_KERNEL`` value with ``neurov study ... --executor processes
--no-plots``, and prints a Markdown table: the path each run used, the MD5
of its ``runs.csv``, the largest relative difference of any metric from
DIR's ``runs.csv[.gz]`` (and where it is), how many runs failed differently,
and whether the rows of the controllers that use no network are the same
byte for byte. The study's own progress goes to standard error. A run of
the robustness study takes about a minute of CPU per path.
"""

from __future__ import annotations

import argparse
import gzip
import hashlib
import json
import os
import subprocess
import sys
import tempfile
from pathlib import Path

import numpy as np
import pandas as pd

ROOT = Path(__file__).resolve().parent.parent
KEY = ["scenario", "controller", "sample"]
#: Columns that say what a run was, not what it measured.
NOT_METRICS = {"vehicle", "failed", "noise_seed", "error_kind", "error"}


def runs_text(folder: Path) -> bytes:
    """The bytes of `folder`'s runs.csv (or of its runs.csv.gz, unpacked)."""
    plain, packed = folder / "runs.csv", folder / "runs.csv.gz"
    if plain.is_file():
        return plain.read_bytes()
    if packed.is_file():
        return gzip.decompress(packed.read_bytes())
    raise FileNotFoundError(f"{folder}: no runs.csv or runs.csv.gz")


def study_file(folder: Path) -> Path:
    """The study file that wrote `folder`, from its study.json's ``source``."""
    source = json.loads((folder / "study.json").read_text())["source"]
    path = Path(source) if Path(source).is_absolute() else ROOT / source
    if not path.is_file():
        raise FileNotFoundError(f"{folder / 'study.json'}: its source {source} is not a file")
    return path


def path_taken(kernel: str) -> str:
    """The path the RBF loops take here with NEUROV_KERNEL=`kernel`."""
    env = dict(os.environ, NEUROV_KERNEL=kernel)
    done = subprocess.run([sys.executable, "-W", "ignore", "-c", "import neurov.kernels as k; print(k.kernel_path())"],
                          env=env, capture_output=True, text=True, check=True)
    return done.stdout.strip()


def run_study(study: Path, kernel: str, out: Path, workers: int) -> None:
    """Runs `study` into `out` with NEUROV_KERNEL=`kernel`, its progress on
    standard error."""
    env = dict(os.environ, NEUROV_KERNEL=kernel, PYTHONHASHSEED="0")
    print(f"kernel_paths: NEUROV_KERNEL={kernel}: neurov study {study.relative_to(ROOT)} --out {out}",
          file=sys.stderr, flush=True)
    subprocess.run([sys.executable, "-m", "neurov", "study", str(study), "--out", str(out), "--workers",
                    str(workers), "--executor", "processes", "--no-plots"],
                   cwd=ROOT, env=env, check=True, stdout=sys.stderr)


def _relative(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """|a - b| / max(|a|, |b|), 0 where both are equal (infinities and NaN
    included) and infinite where one is finite and the other not."""
    with np.errstate(divide="ignore", invalid="ignore"):
        d = np.abs(a - b) / np.maximum(np.abs(a), np.abs(b))
    same = (a == b) | (np.isnan(a) & np.isnan(b))
    return np.where(same, 0.0, np.where(np.isfinite(d), d, np.inf))


def compare(new: pd.DataFrame, old: pd.DataFrame) -> tuple[float, str, int]:
    """The largest relative difference of a metric between two runs tables
    of the same study, where it is, and the number of runs whose failure
    differs."""
    a, b = new.set_index(KEY).sort_index(), old.set_index(KEY).sort_index()
    if not a.index.equals(b.index):
        raise ValueError("the two runs tables do not hold the same runs")
    worst, where = 0.0, ""
    for column in a.columns:
        if column in NOT_METRICS or column.startswith("p_") or not pd.api.types.is_numeric_dtype(a[column]):
            continue
        d = _relative(a[column].to_numpy(float), b[column].to_numpy(float))
        if d.size and d.max() > worst:
            i = int(d.argmax())
            scenario, controller, sample = a.index[i]
            worst, where = float(d.max()), f"{column} of {controller}, {scenario}, sample {sample}"
    failed = int((a["failed"].astype(bool) != b["failed"].astype(bool)).sum())
    return worst, where, failed


def _without_network(runs: pd.DataFrame) -> str:
    """The rows of the controllers that use no RBF network, as CSV text."""
    return runs[~runs["controller"].str.startswith("nn")].to_csv(index=False)


def main(args: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("folder", type=Path, help="a study folder kept under docs/data/ (study.json, runs.csv[.gz])")
    p.add_argument("--paths", default="avx512,avx2,generic",
                   help="NEUROV_KERNEL values to run, comma-separated (default: %(default)s; "
                        "a path this CPU lacks is run once, as the path it falls back to)")
    p.add_argument("--workers", type=int, default=2, help="worker processes per run (default: %(default)s)")
    a = p.parse_args(args)
    folder = a.folder if a.folder.is_absolute() else ROOT / a.folder
    kernels = [k.strip() for k in a.paths.split(",") if k.strip()]
    if not kernels:
        p.error("--paths: expected at least one of avx512, avx2, generic")
    committed = runs_text(folder)
    old = pd.read_csv(folder / ("runs.csv" if (folder / "runs.csv").is_file() else "runs.csv.gz"))
    study = study_file(folder)
    name = folder.relative_to(ROOT).as_posix() if folder.is_relative_to(ROOT) else str(folder)
    rows, seen = [], set()
    with tempfile.TemporaryDirectory() as tmp:
        for kernel in kernels:
            out = Path(tmp) / kernel
            used = path_taken(kernel)
            if used in seen or (kernel != "generic" and not used.startswith(kernel)):
                rows.append(f"| `{kernel}` | not run: this CPU or build lacks it (it would take {used}) "
                            "| | | | | | |")
                continue
            seen.add(used)
            run_study(study, kernel, out, a.workers)
            text = runs_text(out)
            new = pd.read_csv(out / "runs.csv")
            worst, where, failed = compare(new, old)
            n, o = (f.sort_values(KEY, kind="stable").reset_index(drop=True) for f in (new, old))
            plain = _without_network(n) == _without_network(o)
            rows.append(f"| `{kernel}` | {used} | `{hashlib.md5(text).hexdigest()}` | {len(new)} | "
                        f"{worst:.1e} | {where or 'none'} | {failed} | {'yes' if plain else 'no'} |")
    print(f"| `NEUROV_KERNEL` | path run | MD5 of `runs.csv` | runs | largest relative difference from "
          f"{name} | where | runs failed differently | rows without a network the same |")
    print("|---|---|---|---|---|---|---|---|")
    print(f"| {name} (committed) | | `{hashlib.md5(committed).hexdigest()}` | {len(old)} | | | | |")
    print("\n".join(rows))
    return 0


if __name__ == "__main__":
    sys.exit(main())
