"""The NN step's time against where its storage lands on the heap.

`_bench.time_controller_steps` copies the controller before each timed loop,
so the weights and the basis get fresh heap blocks whose offset from a 32- or
64-byte boundary (which the AVX2 and AVX-512 kernels load at) depends on all
that was allocated before (the packed centres start on a cache line whatever
the offset). This shifts the heap by 16-byte steps (a buffer
kept alive before each copy) and times the step at each offset, so that a
difference between two builds can be told from an offset's effect:

    pip install -Ccmake.define.NEUROV_BUILD_BENCH=ON .
    python bench/heap_offset.py --centres 64 --offsets 8
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))

import compare  # noqa: E402  (this folder's step inputs and controller)

from neurov import _bench  # noqa: E402


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--centres", type=int, default=64, help="N, the network's centres (default 64)")
    parser.add_argument("--offsets", type=int, default=8, help="16-byte heap shifts to try (default 8)")
    parser.add_argument("--steps", type=int, default=100_000, help="steps per timed loop")
    args = parser.parse_args()
    for name in ("centres", "offsets", "steps"):
        if getattr(args, name) < 1:
            parser.error(f"argument --{name}: expected >= 1, got {getattr(args, name)}")
    inputs = compare.step_inputs(256)
    centres = compare.centres(args.centres)
    kept = []
    print(f"NN step, N = {args.centres}, C++ loop (best of 5), by heap shift:")
    for shift in range(args.offsets):
        kept.append(bytearray(600 + 16 * shift))
        t = _bench.time_controller_steps(compare.neurov_controller(centres), inputs, args.steps, 5)
        print(f"  +{16 * shift:4d} B  {t * 1e9:7.0f} ns")


if __name__ == "__main__":
    main()
