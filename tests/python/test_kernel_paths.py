"""NEUROV_KERNEL pins the copy of the RBF loops (generic, avx2, avx512), and
the copies agree to the tolerance docs/studies.md states: a closed-loop NN run
(the shipped BlueROV2 helix with its yaw disturbance, the robustness study's
worst case) gives the same trajectory to 1e-9 relative, and a controller
without a network gives it bit for bit. Each path runs in its own process
because the choice is read once, at the first step."""
from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

import neurov

SCENARIO = Path(neurov.__file__).with_name("scenarios") / "bluerov2_helix_disturbed.toml"
# The closed loop amplifies the last-bit differences of FMA and lane splits;
# the worst over the 3000 runs of the robustness study was 4.6e-9 (mean |tau|
# in yaw), docs/studies.md.
TOLERANCE = 1e-8

CHILD = r"""
import json, sys
import numpy as np
import neurov
from neurov import _core
from neurov.config.reading import load_scenario
from neurov.running.simulation import simulate
s = load_scenario(sys.argv[1])
if sys.argv[3] == "pd":
    s = s.replace(controller=neurov.config.scenario.ControllerSpec(type="pd", kp=np.full(6, 20.0),
                                                            kd=np.full(6, 20.0)))
r = simulate(s.replace(duration=float(sys.argv[2])))
np.savez(sys.argv[4], eta=r.eta, tau=r.tau_demanded)
print(json.dumps({"kernel": _core._kernel_isa()}))
"""


def run(kernel: str, controller: str, tmp_path: Path, duration: float = 40.0) -> tuple[str, dict]:
    out = tmp_path / f"{kernel}_{controller}.npz"
    env = dict(os.environ, NEUROV_KERNEL=kernel)
    proc = subprocess.run([sys.executable, "-c", CHILD, str(SCENARIO), str(duration), controller,
                           str(out)], env=env, capture_output=True, text=True, check=True)
    with np.load(out) as data:
        return json.loads(proc.stdout.splitlines()[-1])["kernel"], dict(data)


def best_path() -> str:
    return neurov._core._kernel_isa()


@pytest.mark.skipif(best_path() not in ("avx2", "avx512"),
                    reason="no runtime dispatch in this build or CPU: one path only")
def test_paths_agree_to_the_stated_tolerance(tmp_path: Path) -> None:
    kernel, generic = run("generic", "nn", tmp_path)
    assert kernel not in ("avx2", "avx512")
    paths = ["avx2", "avx512"] if best_path() == "avx512" else ["avx2"]
    for path in paths:
        kernel, other = run(path, "nn", tmp_path)
        assert kernel == path
        for name in ("eta", "tau"):
            scale = np.max(np.abs(generic[name]))
            diff = np.max(np.abs(other[name] - generic[name]))
            assert diff <= TOLERANCE * scale, (path, name, diff / scale)
        # Not identical, or the test would not see the paths at all.
        assert not np.array_equal(other["tau"], generic["tau"]), path


@pytest.mark.skipif(best_path() not in ("avx2", "avx512"),
                    reason="no runtime dispatch in this build or CPU: one path only")
def test_without_a_network_the_paths_are_bit_for_bit_equal(tmp_path: Path) -> None:
    _, generic = run("generic", "pd", tmp_path, duration=20.0)
    _, other = run(best_path(), "pd", tmp_path, duration=20.0)
    assert np.array_equal(other["eta"], generic["eta"])
    assert np.array_equal(other["tau"], generic["tau"])


@pytest.mark.parametrize("request_, expected", [("generic", "generic"), ("avx2", "avx2"),
                                                ("avx512", "avx512"), ("auto", "best"),
                                                ("", "best"), ("sse9", "best")])
def test_neurov_kernel_pins_the_path_capped_at_the_cpu(request_: str, expected: str) -> None:
    order = ["generic", "avx2", "avx512"]
    best = best_path() if best_path() in order else "generic"
    want = best if expected == "best" else order[min(order.index(expected), order.index(best))]
    env = dict(os.environ, NEUROV_KERNEL=request_)
    out = subprocess.run([sys.executable, "-c", "import neurov._core as c; print(c._kernel_isa())"],
                         env=env, capture_output=True, text=True, check=True).stdout.strip()
    assert (out if out in ("avx2", "avx512") else "generic") == want


@pytest.mark.parametrize("request_", ["sse9", "AVX2", "fast"])
def test_a_misspelt_neurov_kernel_is_a_warning_naming_it(request_: str) -> None:
    env = dict(os.environ, NEUROV_KERNEL=request_)
    proc = subprocess.run([sys.executable, "-W", "error::RuntimeWarning", "-c", "import neurov"],
                          env=env, capture_output=True, text=True)
    assert proc.returncode != 0
    assert f"NEUROV_KERNEL={request_!r} is not one of 'generic', 'avx2', 'avx512', 'auto'" in proc.stderr


@pytest.mark.parametrize("request_", ["generic", "auto", ""])
def test_a_valid_neurov_kernel_imports_silently(request_: str) -> None:
    env = dict(os.environ, NEUROV_KERNEL=request_)
    proc = subprocess.run([sys.executable, "-W", "error::RuntimeWarning", "-c", "import neurov"],
                          env=env, capture_output=True, text=True)
    assert proc.returncode == 0, proc.stderr
