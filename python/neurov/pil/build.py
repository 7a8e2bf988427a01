"""The firmware image of processor-in-the-loop runs, built on first use and
cached: the task of ``examples/firmware/cortex-m7/pil`` over neurov's C
interface, for QEMU's Cortex-M7 board ``mps2-an500`` (with the Arm GNU
toolchain, ``arm-none-eabi-gcc``) or for the host (the same float controller
run natively, with ``cc``/``c++``). The sources ship in the package
(``neurov/pil/firmware``, installed there by CMake); in a source checkout
they are read where they live. An image is cached under
``$NEUROV_CACHE_DIR`` (default ``$XDG_CACHE_HOME/neurov`` or
``~/.cache/neurov``), in ``pil/<hash>/``, the hash of its sources, flags and
compiler, so a change of any rebuilds it."""

from __future__ import annotations

import hashlib
import os
import re
import shutil
import struct
import subprocess
import sys
import tempfile
from collections.abc import Callable
from pathlib import Path

from neurov.files import PACKAGE_DIR
from neurov.pil.framing import PILError

__all__ = ["ARM_FLAGS", "EXCEPTION_FRAME_BYTES", "build_image", "cache_dir", "firmware_tree", "image_sizes", "static_stack"]

#: The Cortex-M7 code generation: FPv5 with double precision (QEMU's
#: cortex-m7 reports MVFR0 0x10110221, single and double), hard-float ABI,
#: -Os as in cmake/toolchains/arm-none-eabi-cortex-m7.cmake.
ARM_FLAGS = ("-mcpu=cortex-m7", "-mfpu=fpv5-d16", "-mfloat-abi=hard", "-mthumb", "-Os")
_COMMON = ("-DNDEBUG", "-ffunction-sections", "-fdata-sections")
_CXX = ("-std=c++17", "-fno-exceptions", "-fno-rtti", "-fno-threadsafe-statics")
_LIBRARY = ("c_api.cpp", "c_api_allocation.cpp", "c_api_estimator.cpp")
_TASK = ("pil_task.c", "pil_frame.c")


def firmware_tree() -> tuple[Path, Path, Path]:
    """(the firmware folder with pil/, the include folder with neurov/, the
    folder of c_api*.cpp): the package's copy, else the source checkout's."""
    shipped = PACKAGE_DIR / "pil" / "firmware"
    if (shipped / "cortex-m7").is_dir():
        return shipped / "cortex-m7", shipped / "include", shipped / "src"
    root = PACKAGE_DIR.parent.parent
    if (root / "examples" / "firmware" / "cortex-m7" / "pil").is_dir():
        return root / "examples" / "firmware" / "cortex-m7", root / "cpp" / "include", root / "cpp" / "src"
    raise PILError(f"the firmware sources are missing: neither {shipped} nor a source checkout around "
                   f"{PACKAGE_DIR}; reinstall neurov or pass --image")


def cache_dir() -> Path:
    """Where built images are kept (see the module)."""
    base = os.environ.get("NEUROV_CACHE_DIR") or os.path.join(
        os.environ.get("XDG_CACHE_HOME") or os.path.expanduser("~/.cache"), "neurov")
    return Path(base) / "pil"


def _eigen(include: Path) -> Path:
    candidates = [os.environ.get("NEUROV_EIGEN_INCLUDE", ""), str(include.parent / "eigen"),
                  "/usr/include/eigen3", "/usr/local/include/eigen3"]
    for c in candidates:
        if c and (Path(c) / "Eigen" / "Core").is_file():
            return Path(c)
    raise PILError("Eigen's headers (Eigen/Core) were not found: set NEUROV_EIGEN_INCLUDE to the folder "
                   "holding Eigen/, or install them (Debian: libeigen3-dev)")


def _tool(name: str, package: str) -> str:
    path = shutil.which(name)
    if path is None:
        raise PILError(f"{name} not found: install {package}, or pass --image with a prebuilt image")
    return path


def build_image(centres: int, *, target: str = "mps2-an500", kd_scale: float = 1.0) -> Path:
    """The image for `target` ("mps2-an500": an ELF for QEMU; "host": a host
    program) with N = `centres`, built unless cached; `kd_scale` != 1 builds
    the deliberately changed firmware of the tests (K_d times it)."""
    if target not in ("mps2-an500", "host"):
        raise ValueError(f"argument 'target' must be 'mps2-an500' or 'host', got {target!r}")
    firmware, include, src = firmware_tree()
    pil = firmware / "pil"
    arm = target != "host"
    if arm:
        cc = _tool("arm-none-eabi-gcc", "the Arm GNU toolchain (Debian: gcc-arm-none-eabi "
                   "libnewlib-arm-none-eabi libstdc++-arm-none-eabi-newlib)")
        cxx = _tool("arm-none-eabi-g++", "the Arm GNU toolchain's C++ (Debian: libstdc++-arm-none-eabi-newlib)")
        flags = [*ARM_FLAGS, *_COMMON]
    else:
        cc, cxx = _tool("cc", "a C compiler"), _tool("c++", "a C++ compiler")
        flags = ["-O2", *_COMMON]
    size = [f"-DNEUROV_C_CENTRES={int(centres)}"]
    defines = size + ([f"-DPIL_KD_SCALE={kd_scale!r}f"] if kd_scale != 1.0 else [])
    includes = [f"-I{include}", f"-I{pil}", "-isystem", str(_eigen(include))]
    c_sources = [pil / s for s in _TASK] + ([pil / "board_mps2_an500.c", firmware / "startup.c"] if arm
                                             else [pil / "board_host.c"])
    cpp_sources = [src / s for s in _LIBRARY]
    # -fcallgraph-info=su: the frames and calls static_stack() adds up.
    stack = ["-fcallgraph-info=su"] if arm else []
    version = _version(cc)
    # The C interface, compiled once per toolchain and N (a changed task or
    # gain relinks it).
    lib_flags = [*flags, *stack, *_CXX, *size, *includes]
    library = _cached([cxx, *lib_flags, version], [*cpp_sources, *sorted(include.rglob("*.h*")), *src.glob("*.hpp")],
                      lambda work: _compile(cxx, lib_flags, cpp_sources, work))
    name = "neurov_pil.elf" if arm else "neurov_pil_host"
    c_flags = [*flags, *stack, "-std=c11", "-Wall", "-Wextra", *defines, *includes]
    scripts = [pil / "mps2_an500.ld", firmware / "sections.ld"] if arm else []

    def make(work: Path) -> None:
        link = [cc, *flags, *_compile(cc, c_flags, c_sources, work), *map(str, sorted(library.glob("*.o")))]
        if arm:
            link += ["-nostartfiles", "--specs=nano.specs", "-Wl,--gc-sections", f"-L{firmware}",
                     f"-T{pil / 'mps2_an500.ld'}", f"-Wl,-Map={work / 'neurov_pil.map'}", "-lm"]
        else:
            link += ["-lstdc++", "-lm"]
        _run([*link, "-o", str(work / name)])
        for graph in library.glob("*.ci"):
            shutil.copyfile(graph, work / graph.name)

    return _cached([cc, *c_flags, version, library.name], [*c_sources, *scripts, *sorted(pil.glob("*.h"))], make) / name


def _cached(parts: list[str], files: list[Path], make: Callable[[Path], object]) -> Path:
    """The cache's folder for `parts` and the contents of `files`, made by
    ``make(folder)`` unless it is there (built in a temporary folder and
    renamed into place, so that a stopped build leaves nothing half made)."""
    digest = hashlib.sha256()
    for part in parts:
        digest.update(part.encode() + b"\0")
    for path in files:
        digest.update(path.name.encode() + b"\0" + path.read_bytes())
    out = cache_dir() / digest.hexdigest()[:16]
    if out.is_dir():
        return out
    out.parent.mkdir(parents=True, exist_ok=True)
    with tempfile.TemporaryDirectory(dir=out.parent, prefix=".building-") as tmp:
        work = Path(tmp)
        make(work)
        try:
            os.rename(work, out)
        except OSError:  # made meanwhile by another run: theirs is the same
            pass
        work.mkdir(exist_ok=True)  # for TemporaryDirectory's clean-up
    return out


def _compile(cxx: str, flags: list[str], sources: list[Path], work: Path) -> list[str]:
    """Two compilers at a time (Eigen makes each take seconds)."""
    objects, running = [], []
    for s in sources:
        obj = str(work / (s.stem + ".o"))
        objects.append(obj)
        running.append(subprocess.Popen([cxx, *flags, "-c", str(s), "-o", obj], stdout=subprocess.PIPE,
                                        stderr=subprocess.STDOUT, text=True))
        if len(running) == 2:
            _finish(running.pop(0))
    for p in running:
        _finish(p)
    return objects


def _finish(process: subprocess.Popen[str]) -> None:
    out, _ = process.communicate()
    if process.returncode != 0:
        raise PILError(f"building the firmware failed: {' '.join(map(str, process.args))}\n{out}")  # type: ignore[arg-type]


def _run(argv: list[str]) -> None:
    _finish(subprocess.Popen(argv, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True))


def _version(cc: str) -> str:
    return subprocess.run([cc, "--version"], capture_output=True, text=True).stdout


#: Bytes an interrupt adds to the stack it lands on: the exception frame
#: with the FPU's registers (ARMv7-M: 26 words, 8-byte aligned, plus one).
EXCEPTION_FRAME_BYTES = 108


def static_stack(image: Path) -> dict[str, int] | None:
    """The static bound of the image's main stack, from GCC's call graphs
    (the firmware's stack_usage.py): the deepest path from Reset_Handler,
    plus the deepest interrupt handler and its exception frame. None for an
    image without its build's call graphs (a prebuilt one, say)."""
    graphs = sorted(str(p) for p in image.parent.glob("*.ci"))
    if not graphs:
        return None
    script = firmware_tree()[0] / "stack_usage.py"
    out = subprocess.run([sys.executable, str(script), "--entry", "Reset_Handler|SysTick_Handler|UART0RX_Handler",
                          *graphs], capture_output=True, text=True)
    depths = {m.group(1): int(m.group(2)) for m in re.finditer(r"^(\w+)\s+(\d+) bytes$", out.stdout, re.M)}
    if out.returncode != 0 or "Reset_Handler" not in depths:
        raise PILError(f"the stack bound failed: {out.stdout}{out.stderr}")
    handlers = max((v for k, v in depths.items() if k != "Reset_Handler"), default=0)
    return {"reset_to_deepest_call": depths["Reset_Handler"], "deepest_interrupt": handlers,
            "exception_frame": EXCEPTION_FRAME_BYTES,
            "bound": depths["Reset_Handler"] + handlers + EXCEPTION_FRAME_BYTES}


def image_sizes(image: Path) -> dict[str, int]:
    """Flash (code, constants, .data's initial values) and static RAM
    (.data + .bss) of an ELF32 image, from its section headers, in bytes."""
    try:
        data = Path(image).read_bytes()
    except OSError as e:
        raise PILError(f"argument 'image': cannot read {str(image)!r}: {e.strerror or e}") from None
    if data[:5] != b"\x7fELF\x01" or len(data) < 0x34 or struct.unpack_from("<H", data, 0x12)[0] != 40:
        raise PILError(f"argument 'image': {str(image)!r} is not a 32-bit ELF file for Arm")
    shoff, = struct.unpack_from("<I", data, 0x20)
    shentsize, shnum = struct.unpack_from("<HH", data, 0x2E)
    flash = ram = 0
    for i in range(shnum):
        _, kind, flags, _, _, size = struct.unpack_from("<IIIIII", data, shoff + i * shentsize)
        if not flags & 2:  # SHF_ALLOC
            continue
        if kind != 8:  # not SHT_NOBITS: stored in the image
            flash += size
        if flags & 1:  # SHF_WRITE
            ram += size
    return {"flash_bytes": flash, "ram_bytes": ram}
