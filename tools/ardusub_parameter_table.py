"""Prints the ArduSub parameters neurov's ardusub controller reads as a
Markdown table (name, default, documented range, unit, meaning), from the
one C++ table (neurov/control/ardusub_parameters.hpp) through
neurov._core.ARDUSUB_PARAMETERS. Used by docs/ardusub.md:

    python tools/ardusub_parameter_table.py
"""

from __future__ import annotations

from neurov.laws.ardusub_params import PARAMETERS


def main() -> None:
    print("| parameter | default | documented range | unit | meaning |")
    print("|---|---|---|---|---|")
    for p in PARAMETERS.values():
        print(f"| `{p.name}` | {p.default:g} | {p.min:g} to {p.max:g} | {p.unit} | {p.doc} |")


if __name__ == "__main__":
    main()
