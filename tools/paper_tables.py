"""Prints one of the tables ``neurov paper`` prints, without its figures or
files: the source of the generated tables of docs/paper-reproduction.md.

    python tools/paper_tables.py results   # the experiments' metrics
    python tools/paper_tables.py sweep     # Fig. 5 over disturbance amplitude and frequency
"""

from __future__ import annotations

import sys

from neurov.paper.experiments import paper_tables

if __name__ == "__main__":
    which = sys.argv[1] if len(sys.argv) > 1 else ""
    if which not in ("results", "sweep"):
        sys.exit("usage: python tools/paper_tables.py results|sweep")
    results, sweep = paper_tables()
    print(results if which == "results" else sweep)
