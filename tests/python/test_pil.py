"""Processor in the loop (neurov.pil): the frames, and short runs on QEMU's
mps2-an500 against the host build of the same task (CI installs
gcc-arm-none-eabi and qemu-system-arm; without them the runs are skipped)."""

from __future__ import annotations

import binascii
import io
import json
import os
import shutil
import signal
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest

import neurov
from neurov.pil import framing

TOOLS = shutil.which("arm-none-eabi-gcc") and shutil.which("qemu-system-arm")
needs_board = pytest.mark.skipif(not TOOLS and not os.environ.get("NEUROV_REQUIRE_PIL"),
                                 reason="needs arm-none-eabi-gcc and qemu-system-arm")


def test_crc_is_ccitt_false_and_frames_round_trip() -> None:
    assert binascii.crc_hqx(b"123456789", 0xFFFF) == 0x29B1  # the CRC-16/CCITT-FALSE check value
    reader = framing.FrameReader()
    a, b = framing.encode(b"M", b"\x01\x02\x03"), framing.encode(b"S", b"")
    assert reader.feed(b"\x00junk" + a[:4]) == []
    assert reader.feed(a[4:] + b) == [(b"M", b"\x01\x02\x03"), (b"S", b"")]
    bad = bytearray(a)
    bad[6] ^= 1
    assert reader.feed(bytes(bad) + b) == [(b"S", b"")] and reader.refused == 1


def test_faults_are_parsed_by_step_and_refused_when_unknown() -> None:
    from neurov.pil.command import parse_faults

    assert parse_faults(["nan@1.0", "drop@2"], 0.2) == {5: "nan", 10: "drop"}
    with pytest.raises(ValueError, match="--fault"):
        parse_faults(["smoke@1"], 0.2)


@pytest.fixture(scope="module")
def cache(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """Images built once for this module (unless NEUROV_CACHE_DIR names a cache)."""
    path = Path(os.environ.get("NEUROV_CACHE_DIR") or tmp_path_factory.mktemp("pil-cache"))
    old = os.environ.get("NEUROV_CACHE_DIR")
    os.environ["NEUROV_CACHE_DIR"] = str(path)
    yield path
    if old is None:
        del os.environ["NEUROV_CACHE_DIR"]


@needs_board
def test_bluerov2_on_the_board_matches_the_host_build_and_loads(cache: Path, tmp_path: Path) -> None:
    from neurov.pil.command import run_pil

    pil = run_pil("bluerov2_depth_step", tmp_path / "out", duration=20.0, stream=io.StringIO())
    assert pil["from_host_float"]["within"] and pil["from_double"]["within"], pil["from_host_float"]
    assert pil["board"]["cpuid"] == "0x411fc272"  # Cortex-M7
    assert pil["faults"]["counts"] == {}
    assert 0 < pil["stack"]["painted_bytes"] <= pil["stack"]["static_bound"]["bound"]
    assert pil["instructions_per_step"]["steps"] == pil["steps"] - 1 or pil["instructions_per_step"]["steps"] == pil["steps"]
    result = neurov.load_result(tmp_path / "out")
    assert len(result.t) == pil["steps"]
    assert json.loads((tmp_path / "out" / "pil.json").read_text())["scenario"] == "bluerov2_depth_step"


@needs_board
def test_the_image_has_no_heap_exceptions_or_rtti(cache: Path) -> None:
    from neurov.pil.build import build_image

    symbols = subprocess.run(["arm-none-eabi-nm", str(build_image(64))], capture_output=True, text=True,
                             check=True).stdout.split()
    banned = [s for s in symbols if s in ("malloc", "free", "calloc", "realloc", "_sbrk", "__cxa_throw",
                                          "__gxx_personality_v0", "__cxa_allocate_exception")
              or s.startswith(("_Znw", "_Zna", "_Zdl", "_Zda", "_ZTI", "_ZTS"))]
    assert "Reset_Handler" in symbols and not banned, banned


@needs_board
def test_a_gain_change_in_the_firmware_leaves_the_tolerance(cache: Path) -> None:
    """K_d times 1.01 on the board: the comparison with the host must fail."""
    from neurov.pil.command import run_pil

    pil = run_pil("bluerov2_depth_step", duration=20.0, kd_scale=1.01, stream=io.StringIO())
    assert not pil["from_host_float"]["within"], pil["from_host_float"]


@needs_board
def test_faults_are_answered_with_the_safe_command_and_counted(cache: Path) -> None:
    from neurov.pil.command import run_pil

    faults = ["nan@4", "range@5", "garble@6", "drop@7"]
    pil = run_pil("bluerov2_depth_step", duration=10.0, faults=faults, watchdog_ms=300,
                  stream=io.StringIO())
    counts = pil["faults"]["counts"]
    assert counts == {"non_finite_input": 1, "out_of_range": 1, "bad_frame": 1, "timeout": 1}, counts
    assert pil["faults"]["host_float_counts"] == counts
    assert pil["from_host_float"]["within"]  # the same faults on both: the same run
    faulted = [pil["per_step"]["fault"][k] for k in (20, 25, 30, 35)]
    assert faulted == ["none", "out_of_range", "bad_frame", "timeout"]
    assert pil["per_step"]["status"][20] == 2  # NON_FINITE_INPUT


@needs_board
@pytest.mark.parametrize("how", [signal.SIGKILL, signal.SIGTERM])
def test_qemu_dies_with_a_stopped_neurov_pil(cache: Path, how: signal.Signals) -> None:
    parent = subprocess.Popen([sys.executable, "-m", "neurov", "pil", "bluerov2_depth_step"],
                              stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    qemu = None
    try:
        for _ in range(600):
            qemu = next((p for p in Path("/proc").glob("[0-9]*") if _parent_of(p) == parent.pid
                         and "qemu" in _name_of(p)), None)
            if qemu is not None or parent.poll() is not None:
                break
            time.sleep(0.1)
        assert qemu is not None, f"neurov pil did not start QEMU (exit {parent.poll()})"
        parent.send_signal(how)
        assert parent.wait() == (143 if how == signal.SIGTERM else -signal.SIGKILL)
    finally:  # a failed test leaves no neurov pil behind
        if parent.poll() is None:
            parent.kill()
            parent.wait()
    for _ in range(100):
        if not qemu.exists() or _state_of(qemu) == "Z":
            break
        time.sleep(0.1)
    assert not qemu.exists() or _state_of(qemu) == "Z"


def _stat(p: Path) -> list[str]:
    try:
        text = (p / "stat").read_text()
    except OSError:
        return []
    return text[text.rindex(")") + 2:].split()


def _parent_of(p: Path) -> int:
    s = _stat(p)
    return int(s[1]) if s else -1


def _state_of(p: Path) -> str:
    s = _stat(p)
    return s[0] if s else ""


def _name_of(p: Path) -> str:
    try:
        return (p / "comm").read_text()
    except OSError:
        return ""
