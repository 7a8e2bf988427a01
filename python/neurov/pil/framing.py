"""The frames between ``neurov pil`` and the board, the host's half of the
firmware's ``pil_frame.h`` and ``pil_task.c`` (examples/firmware/cortex-m7/pil):

``0xA5 0x5A | type (1 byte) | length (2 bytes) | payload | CRC (2 bytes)``,
little-endian, floats IEEE-754 single, the CRC-16/CCITT-FALSE (polynomial
0x1021, initial 0xFFFF: :func:`binascii.crc_hqx`) over type, length and
payload. Each function here packs or unpacks one payload."""

from __future__ import annotations

import binascii
import struct
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from neurov.errors import NeurovError

__all__ = ["FAULTS", "PILError", "STATUSES", "MAX_PAYLOAD", "Answer", "Hello", "Report", "FrameReader", "config_payload", "encode",
           "measurement_payload", "parse_answer", "parse_hello", "parse_report"]


class PILError(NeurovError):
    """Processor in the loop could not start or go on: a missing tool or
    image, a board that did not boot or refused its configuration."""


SYNC = b"\xa5\x5a"
MAX_PAYLOAD = 8192
CONFIG, MEASUREMENT, STATS = b"C", b"M", b"S"
HELLO, ACK, COMMAND, REPORT = b"H", b"A", b"T", b"R"
NO_SEQ = 0xFFFFFFFF
#: The board's reasons for a safe command (PIL_FAULT_* of pil_frame.h), by code.
FAULTS = {0: "none", 1: "bad_frame", 2: "out_of_range", 3: "timeout", 4: "not_configured"}
#: The C interface's status codes (neurov_status), by code.
STATUSES = {0: "ok", 1: "near_singularity", 2: "non_finite_input", 3: "invalid_argument", 4: "non_finite_output"}


def encode(kind: bytes, payload: bytes) -> bytes:
    """One frame of type `kind` around `payload`."""
    if len(payload) > MAX_PAYLOAD:
        raise ValueError(f"a frame's payload is at most {MAX_PAYLOAD} bytes, got {len(payload)}")
    head = kind + struct.pack("<H", len(payload))
    return SYNC + head + payload + struct.pack("<H", binascii.crc_hqx(head + payload, 0xFFFF))


class FrameReader:
    """Frames out of a byte stream fed in pieces; a frame with a bad CRC or
    length is dropped and counted in :attr:`refused`."""

    def __init__(self) -> None:
        self.buffer = bytearray()
        self.refused = 0

    def feed(self, data: bytes) -> list[tuple[bytes, bytes]]:
        """The whole frames (type, payload) completed by `data`."""
        self.buffer += data
        frames = []
        while True:
            start = self.buffer.find(SYNC)
            if start < 0:
                del self.buffer[:-1]
                return frames
            del self.buffer[:start]
            if len(self.buffer) < 5:
                return frames
            length = struct.unpack_from("<H", self.buffer, 3)[0]
            if length > MAX_PAYLOAD:
                self.refused += 1
                del self.buffer[:2]
                continue
            if len(self.buffer) < 7 + length:
                return frames
            body = bytes(self.buffer[2:5 + length])
            crc = struct.unpack_from("<H", self.buffer, 5 + length)[0]
            if binascii.crc_hqx(body, 0xFFFF) == crc:
                frames.append((body[:1], body[3:]))
                del self.buffer[:7 + length]
            else:
                self.refused += 1
                del self.buffer[:2]


def _floats(values: NDArray[np.float64] | list[float], count: int, name: str) -> bytes:
    arr = np.asarray(values, dtype="<f4").reshape(-1)
    if arr.size != count:
        raise ValueError(f"{name}: expected {count} numbers, got {arr.size}")
    return arr.tobytes()


def config_payload(nn: Mapping[str, Any], thrusters: Mapping[str, Any] | None, watchdog_ms: int,
                   limits: tuple[float, float, float, float]) -> bytes:
    """PIL_CONFIG from the NN controller's parameters (`nn`: centres (N, 24),
    widths, input_offset, input_scale, lambda, kd, gamma, dt, modification,
    sigma_m, kappa, w_max, dead_zone) and the thrusters' (matrix (6, n),
    min_thrust, max_thrust, saturation) or None."""
    centres = np.asarray(nn["centres"], dtype=np.float64)
    n_centres = centres.shape[0]
    n = 0 if thrusters is None else np.asarray(thrusters["matrix"]).shape[1]
    saturation = 0 if thrusters is None else int(thrusters["saturation"])
    out = struct.pack("<5I", n_centres, n, watchdog_ms, int(nn["modification"]), saturation)
    out += struct.pack("<6f", *(float(nn[k]) for k in ("dt", "gamma", "sigma_m", "kappa", "w_max", "dead_zone")))
    out += _floats(nn["lambda"], 6, "lambda") + _floats(nn["kd"], 6, "kd") + _floats(list(limits), 4, "limits")
    out += _floats(nn["widths"], n_centres, "widths") + _floats(nn["input_offset"], 24, "input_offset")
    out += _floats(nn["input_scale"], 24, "input_scale") + _floats(centres, 24 * n_centres, "centres")
    if thrusters is not None:
        out += _floats(thrusters["matrix"], 6 * n, "matrix")
        out += _floats(thrusters["min_thrust"], n, "min_thrust") + _floats(thrusters["max_thrust"], n, "max_thrust")
    return out


def measurement_payload(seq: int, *arrays: NDArray[np.float64]) -> bytes:
    """PIL_MEASUREMENT: `seq`, then eta, nu, eta_d, eta_d_dot, eta_d_ddot (6 each)."""
    return struct.pack("<I", seq) + np.concatenate(arrays).astype("<f4").tobytes()


@dataclass(frozen=True)
class Answer:
    """PIL_COMMAND: the measurement it answers (`seq`, :data:`NO_SEQ` for a
    fault not tied to one), the controller's status code, the board's fault
    (:data:`FAULTS`), the step's ticks, tau and s (6) and the thrusts (n)."""

    seq: int
    status: int
    fault: str
    ticks: int
    tau: NDArray[np.float64]
    s: NDArray[np.float64]
    thrust: NDArray[np.float64]


def parse_answer(payload: bytes) -> Answer:
    seq, status, fault, n, _, ticks = struct.unpack_from("<I4BI", payload)
    values = np.frombuffer(payload, dtype="<f4", offset=12).astype(np.float64)
    if values.size != 12 + n:
        raise ValueError(f"a command frame of {len(payload)} bytes for {n} thrusters")
    return Answer(seq, status, FAULTS.get(fault, f"fault_{fault}"), ticks, values[:6], values[6:12], values[12:])


@dataclass(frozen=True)
class Hello:
    """PIL_HELLO: the board's CPUID and MVFR0 registers, tick rate [Hz], N,
    stack bytes reserved."""

    cpuid: int
    mvfr0: int
    tick_hz: int
    centres: int
    stack_size: int


def parse_hello(payload: bytes) -> Hello:
    return Hello(*struct.unpack_from("<5I", payload))


@dataclass(frozen=True)
class Report:
    """PIL_REPORT: stack bytes ever used (painting) and reserved, and the
    board's counts of measurements, refused frames, watchdog timeouts and
    out-of-range measurements, and the longest step [ticks]."""

    stack_used: int
    stack_size: int
    measurements: int
    bad_frames: int
    timeouts: int
    out_of_range: int
    max_step_ticks: int


def parse_report(payload: bytes) -> Report:
    return Report(*struct.unpack_from("<7I", payload))
