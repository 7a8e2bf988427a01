"""Prints the overall table and the head-to-head tables of the ArduSub
league's verdict (docs/data/ardusub_league/league.md, written by
`neurov tune ardusub_league`; see the README there). Used by docs/ardusub.md:

    python tools/ardusub_league_table.py
"""

from __future__ import annotations

from pathlib import Path

LEAGUE = Path(__file__).resolve().parent.parent / "docs" / "data" / "ardusub_league" / "league.md"


def main() -> None:
    text = LEAGUE.read_text()
    sections = text.split("\n## ")
    keep = [s for s in sections[1:] if s.startswith("Over all scenarios") or " against " in s.splitlines()[0]]
    print("\n\n".join("### " + s.strip() for s in keep))


if __name__ == "__main__":
    main()
