"""A request too large for the memory there is is refused before anything
is allocated, naming its size and the memory it would need: a vector
environment of 10^7 envs, a CSV of millions of rows. Each case runs in a
subprocess under an address-space limit (``RLIMIT_AS``, as ``ulimit -v``
sets); before, each ended in a raw MemoryError traceback."""

from __future__ import annotations

import os
import subprocess
import sys
import textwrap
from pathlib import Path

import pytest

import neurov


def _limited(code: str, extra_mib: int, tmp_path: Path) -> subprocess.CompletedProcess[str]:
    """`code` run after its imports under an address-space limit of what the
    process has mapped plus `extra_mib` MiB."""
    script = tmp_path / "limited.py"
    script.write_text(textwrap.dedent(f"""
        import resource, os
        import numpy, pandas, neurov, neurov.cli, neurov.gym
        mapped = int(open("/proc/self/statm").read().split()[0]) * os.sysconf("SC_PAGE_SIZE")
        resource.setrlimit(resource.RLIMIT_AS, (mapped + {extra_mib} * 2**20, resource.RLIM_INFINITY))
    """) + textwrap.dedent(code))
    # The neurov this test imports (installed, or a source tree on PYTHONPATH), not the clone's sources.
    env = {**os.environ, "PYTHONPATH": os.pathsep.join([str(Path(neurov.__file__).parents[1]),
                                                        os.environ.get("PYTHONPATH", "")]),
           "OPENBLAS_NUM_THREADS": "1"}
    return subprocess.run([sys.executable, str(script)], capture_output=True, text=True, env=env, timeout=300,
                          check=False)


@pytest.mark.skipif(not sys.platform.startswith("linux"), reason="RLIMIT_AS and /proc are Linux's")
def test_ten_million_envs_under_a_limit_are_refused_naming_the_memory(tmp_path: Path) -> None:
    pytest.importorskip("gymnasium")
    done = _limited("""
        from neurov.gym import TrackingVectorEnv
        try:
            TrackingVectorEnv(10_000_000)
        except ValueError as e:
            print("refused:", e)
    """, 512, tmp_path)
    assert "MemoryError" not in done.stderr and done.returncode == 0, done.stderr[-2000:]
    assert "refused: argument 'num_envs' = 10000000 (" in done.stdout and "kB an env) would need about" in done.stdout
    assert "left under this process's address-space limit" in done.stdout


@pytest.mark.skipif(not sys.platform.startswith("linux"), reason="RLIMIT_AS and /proc are Linux's")
def test_a_csv_too_large_for_the_memory_is_refused_before_it_is_read(tmp_path: Path) -> None:
    rows = 1_500_000  # 19 columns, 57 MB: about 3 GB of address space as pandas reads it, under 256 MiB more
    line = ",".join(str(i % 10) for i in range(19)) + "\n"
    with open(tmp_path / "big.csv", "w") as f:
        f.write("t," + ",".join(f"c{i}" for i in range(18)) + "\n")
        f.write(line * rows)
    done = _limited(f"""
        import sys
        from neurov.errors import ResultFileError
        try:
            neurov.load_result({str(tmp_path / "big.csv")!r}, scenario="paper_fig3")
        except ResultFileError as e:
            print("load_result:", e)
        sys.exit(neurov.cli.main(["identify", {str(tmp_path / "big.csv")!r}, "--vehicle", "nerov"]))
    """, 256, tmp_path)
    assert "MemoryError" not in done.stderr and "Traceback" not in done.stderr, done.stderr[-2000:]
    said = (r"big.csv: reading about 1,5\d\d,\d\d\d rows of 19 columns \(5\d MiB of CSV\) would need about 3.\d GiB "
            r"of address space, but there is 2\d\d MiB left under this process's address-space limit")
    import re

    assert re.search("load_result: .*" + said, done.stdout), done.stdout
    assert done.returncode == 1 and re.search("neurov: error: .*" + said, done.stderr), done.stderr


def test_a_vector_env_holds_its_envs_state_not_their_rows() -> None:
    """The compiled batch of the vector env keeps a log window of one row,
    emptied as it steps: before, each env held its run's every row (1,251
    rows of paper_fig3, some 880 kB an env: 3.6 GB at 4,096 envs)."""
    gymnasium = pytest.importorskip("gymnasium")
    import numpy as np

    from neurov.gym import TrackingVectorEnv
    from neurov.memory import heap_bytes

    if heap_bytes() is None:
        pytest.skip("the C heap's use cannot be read here (glibc's mallinfo2)")
    k = 256
    before = heap_bytes()
    envs = TrackingVectorEnv(k, "paper_fig3")
    assert envs._batch.log_rows == 1
    envs.reset(seed=0)
    zero = np.zeros((k, 6), dtype=np.float32)
    for _ in range(1300):  # past an episode's end (1,251 rows): the window is emptied, autoresets go on
        envs.step(zero)
    per_env = (heap_bytes() - before) / k
    assert per_env < 200_000, per_env  # the state: 113 kB, 91 kB of it the inline wave storage
    assert gymnasium is not None


def test_memory_no_check_foresaw_is_said_not_a_traceback(monkeypatch: pytest.MonkeyPatch,
                                                          capsys: pytest.CaptureFixture[str]) -> None:
    """A MemoryError past the checks (identify's regressor of a log whose
    CSV fitted, say) ends the command with a sentence and exit status 1."""
    import neurov.identification.cli as identify_cli
    from neurov.cli import main

    def short_of_memory(args: object) -> int:
        raise MemoryError("Unable to allocate 1.07 GiB for an array with shape (999999, 6, 24)")

    monkeypatch.setattr(identify_cli, "run", short_of_memory)
    assert main(["identify", "log.csv", "--vehicle", "nerov"]) == 1
    err = capsys.readouterr().err
    assert err.startswith("neurov: error: out of memory (MemoryError: Unable to allocate 1.07 GiB") and "Traceback" not in err
