"""Prints, as a Markdown table, ArduSub's motor stage replayed against the
real logs of tests/data/logs/ardusub_log_tools (MIT): each log's armed
samples of the pilot's inputs through the ardusub controller's mixing with
the log's own parameters, against the PWMs the log holds
(neurov.laws.ardusub_replay). Used by docs/ardusub.md:

    python tools/ardusub_replay.py
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from neurov.laws.ardusub_replay import replay_mixing

DATA = Path(__file__).resolve().parent.parent / "tests" / "data" / "logs" / "ardusub_log_tools"
# (log of the inputs and PWMs, log of the parameters when another: the same dive's)
LOGS = [("bluerov2_heavy_rc_servo.tlog", "bluerov2_heavy_excerpt.tlog"), ("bluerov2_vectored.BIN", None)]
AXES = ["roll", "pitch", "yaw", "throttle", "forward", "lateral"]


def main() -> None:
    print("| log | FRAME_CONFIG | modes while armed | samples (rate) | largest input per axis "
          "| largest \\|model - logged\\| PWM per motor [us] | samples with every motor within 1 us |")
    print("|---|---|---|---|---|---|---|")
    for log, params in LOGS:
        r = replay_mixing(DATA / log, DATA / params if params else None)
        rate = 1.0 / float(np.median(np.diff(r.t)))
        largest = ", ".join(f"{a} {v:.3g}" for a, v in zip(AXES, np.abs(r.inputs).max(axis=0)) if v > 0)
        worst = " ".join(f"{v:.0f}" for v in np.abs(r.error).max(axis=0))
        within = int(np.sum(np.all(np.abs(r.error) <= 1.0, axis=1)))
        modes = ", ".join("MANUAL (19)" if m == 19 else str(m) for m in sorted(r.modes))
        print(f"| {log} | {r.frame} | {modes} | {len(r.t)} ({rate:.2g} Hz) | {largest} | {worst} "
              f"| {within} of {len(r.t)} |")


if __name__ == "__main__":
    main()
