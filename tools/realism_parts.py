"""The realism study's two parts alone, on the same plants (same seed and
samples): each disturbed scenario with only the delay (``*_delay_only``),
each realistic one without the delay (``*_ekf_only``: sensors and EKF
only). Writes a study folder that ``tools/realism_tables.py`` reads beside
the realism study's own (docs/studies.md, "Ideal and realistic").

    python tools/realism_parts.py DIR [--workers 2]
"""

from __future__ import annotations

import argparse
import dataclasses
import sys

from neurov.study import load_study, run_study


def main(args: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("out", metavar="DIR", help="the study folder to write (a rerun resumes it)")
    p.add_argument("--workers", type=int, default=2, help="worker processes (default: %(default)s)")
    a = p.parse_args(args)
    s = load_study("realism")
    ideal = [x for x in s.scenarios if x.name.endswith("_disturbed")]
    realistic = [x for x in s.scenarios if x.name.endswith("_realistic")]
    parts = [x.replace(name=x.name.replace("_disturbed", "_delay_only"), control_delay=1) for x in ideal]
    parts += [x.replace(name=x.name.replace("_realistic", "_ekf_only"), control_delay=0) for x in realistic]
    run_study(dataclasses.replace(s, name="realism_parts", scenarios=parts, cache={}), a.out, workers=a.workers,
              executor="processes", plots=False)
    return 0


if __name__ == "__main__":  # the worker processes import this file
    sys.exit(main())
