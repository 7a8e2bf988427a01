"""A running board and its link: QEMU's Cortex-M7 system emulator with the
image (``qemu-system-arm -M mps2-an500``, UART0 on a Unix socket, each
instruction one nanosecond of virtual time: ``-icount shift=0``), or the
same task built for the host on a socket pair. The child dies with this
process however it ends (``PR_SET_PDEATHSIG``) and is killed on
:meth:`Board.close`."""

from __future__ import annotations

import ctypes
import os
import shutil
import signal
import socket
import subprocess
import tempfile
import time
from pathlib import Path
from typing import Any

from neurov.pil.framing import (ACK, COMMAND, CONFIG, HELLO, MEASUREMENT, REPORT, STATS, Answer,
                                FrameReader, Hello, PILError, Report, encode, parse_answer, parse_hello,
                                parse_report)

__all__ = ["ICOUNT_SHIFT", "Board"]

#: -icount shift: 2**shift ns of virtual time per instruction.
ICOUNT_SHIFT = 0
_BOOT_SECONDS = 30.0


def _die_with_parent() -> None:
    """In the child before exec: SIGKILL when the parent dies (Linux)."""
    try:
        ctypes.CDLL(None, use_errno=True).prctl(1, signal.SIGKILL)  # PR_SET_PDEATHSIG
    except (OSError, AttributeError):
        pass  # not Linux: close() and the parent's handlers are left


class Board:
    """One board, booted (its hello read: :attr:`hello`). Use as a context
    manager, or call :meth:`close`."""

    def __init__(self, process: subprocess.Popen[bytes], link: socket.socket, kind: str) -> None:
        self.process, self.link, self.kind = process, link, kind
        self.reader = FrameReader()
        self.pending: list[tuple[bytes, bytes]] = []
        try:
            self.hello: Hello = parse_hello(self._expect(HELLO, _BOOT_SECONDS, "boot"))
        except BaseException:
            self.close()
            raise

    @classmethod
    def qemu(cls, image: str | Path) -> Board:
        """QEMU's mps2-an500 running `image` (an ELF)."""
        qemu = shutil.which("qemu-system-arm")
        if qemu is None:
            raise PILError("qemu-system-arm not found: install QEMU's Arm system emulator (Debian: qemu-system-arm)")
        if not Path(image).is_file():
            raise PILError(f"argument 'image': no such file {str(image)!r}")
        workdir = tempfile.TemporaryDirectory(prefix="neurov-pil-")
        path = os.path.join(workdir.name, "uart0")
        server = socket.socket(socket.AF_UNIX, socket.SOCK_STREAM)
        server.bind(path)
        server.listen(1)
        server.settimeout(_BOOT_SECONDS)
        argv = [qemu, "-M", "mps2-an500", "-nodefaults", "-display", "none", "-monitor", "none",
                "-icount", f"shift={ICOUNT_SHIFT}", "-kernel", str(image), "-serial", f"unix:{path}"]
        process = subprocess.Popen(argv, stdin=subprocess.DEVNULL, stdout=subprocess.DEVNULL,
                                   stderr=subprocess.PIPE, preexec_fn=_die_with_parent)
        try:
            link, _ = server.accept()
        except (socket.timeout, OSError) as e:
            process.kill()
            err = process.communicate()[1].decode(errors="replace")
            workdir.cleanup()
            raise PILError(f"QEMU did not connect its UART ({e}): {' '.join(argv)}\n{err}") from None
        finally:
            server.close()
        # Connected: the socket's name is no longer needed, and nothing is
        # left on disk however this process ends.
        workdir.cleanup()
        return cls(process, link, "qemu mps2-an500")

    @classmethod
    def host(cls, program: str | Path) -> Board:
        """The task built for the host (:func:`neurov.pil.build.build_image`
        with target "host"), its stdin/stdout one end of a socket pair."""
        mine, theirs = socket.socketpair()
        process = subprocess.Popen([str(program)], stdin=theirs, stdout=theirs, preexec_fn=_die_with_parent)
        theirs.close()
        return cls(process, mine, "host")

    def close(self) -> None:
        """Stops the board (idempotent)."""
        if self.process.poll() is None:
            self.process.kill()
        self.process.wait()
        if self.process.stderr is not None:
            self.process.stderr.close()
        self.link.close()

    def __enter__(self) -> Board:
        return self

    def __exit__(self, *exc: Any) -> None:
        self.close()

    def send(self, kind: bytes, payload: bytes = b"", *, garble: bool = False) -> None:
        """One frame; with `garble`, one payload byte flipped on the way."""
        frame = bytearray(encode(kind, payload))
        if garble:
            frame[5 + len(payload) // 2] ^= 0x10
        self.link.sendall(frame)

    def receive(self, timeout: float) -> tuple[bytes, bytes] | None:
        """The next frame, or None after `timeout` seconds without one."""
        deadline = time.monotonic() + timeout
        while not self.pending:
            left = deadline - time.monotonic()
            if left <= 0:
                return None
            self.link.settimeout(left)
            try:
                data = self.link.recv(65536)
            except socket.timeout:
                return None
            if not data:
                raise PILError(f"the board ({self.kind}) closed its link{self._exit_note()}")
            self.pending += self.reader.feed(data)
        return self.pending.pop(0)

    def _exit_note(self) -> str:
        try:
            code = self.process.wait(timeout=1.0)
        except subprocess.TimeoutExpired:
            return ""
        err = self.process.stderr.read().decode(errors="replace").strip() if self.process.stderr else ""
        return f" (it exited with status {code}{': ' + err if err else ''})"

    def _expect(self, kind: bytes, timeout: float, what: str) -> bytes:
        frame = self.receive(timeout)
        if frame is None or frame[0] != kind:
            got = "nothing" if frame is None else f"frame {frame[0]!r}"
            raise PILError(f"the board ({self.kind}) sent {got} for its {what} within {timeout:g} s"
                           f"{self._exit_note()}")
        return frame[1]

    def configure(self, payload: bytes) -> None:
        """Sends the configuration; PILError naming the field the board refused."""
        self.send(CONFIG, payload)
        answer = self._expect(ACK, _BOOT_SECONDS, "configuration's answer")
        status, index = int.from_bytes(answer[:4], "little"), int.from_bytes(answer[4:8], "little", signed=True)
        if status != 0:
            field = answer[8:].split(b"\0", 1)[0].decode(errors="replace")
            raise PILError(f"the board refused its configuration (status {status}): field {field!r}, index {index}")

    def measure(self, payload: bytes, *, garble: bool = False, skip: bool = False) -> None:
        """Sends a measurement (`skip`: sends nothing, a frame that never comes)."""
        if not skip:
            self.send(MEASUREMENT, payload, garble=garble)

    def answer(self, timeout: float) -> Answer | None:
        """The next command frame (other frames are dropped), or None."""
        deadline = time.monotonic() + timeout
        while (left := deadline - time.monotonic()) > 0:
            frame = self.receive(left)
            if frame is None:
                return None
            if frame[0] == COMMAND:
                return parse_answer(frame[1])
        return None

    def report(self, timeout: float = 10.0) -> Report:
        """The board's counters and stack mark (commands still in flight are dropped)."""
        self.send(STATS)
        while True:
            frame = self.receive(timeout)
            if frame is None:
                raise PILError(f"the board ({self.kind}) did not report within {timeout:g} s")
            if frame[0] == REPORT:
                return parse_report(frame[1])


