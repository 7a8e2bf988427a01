"""The processor-in-the-loop table of docs/firmware.md, from the pil.json
files that `neurov pil SCENARIO --out docs/data/pil/SCENARIO` wrote:

    python tools/pil_table.py docs/data/pil/paper_fig3 docs/data/pil/bluerov2_depth_step
"""

import json
import sys
from pathlib import Path


def main(folders: list[str]) -> int:
    print("| scenario | steps | max position difference from the host float run | from `neurov run` (double) "
          "| instructions per step, mean / max | stack painted / static bound | flash / RAM | link faults |")
    print("|---|---|---|---|---|---|---|---|")
    for folder in folders:
        p = json.loads((Path(folder) / "pil.json").read_text(encoding="utf-8"))
        h, d, i, s, img = (p["from_host_float"], p["from_double"], p["instructions_per_step"], p["stack"],
                           p["image"])
        faults = ", ".join(f"{k} {v}" for k, v in sorted(p["faults"]["counts"].items())) or "none"
        print(f"| {p['scenario']} | {p['steps']} | {h['max_position_m']:.2g} m (tolerance {h['tolerance_m']:g} m) "
              f"| {d['max_position_m']:.2g} m (limit {d['limit_m']:g} m) | {i['mean']:.0f} / {i['max']:.0f} "
              f"| {s['painted_bytes']} / {s['static_bound']['bound']} B | {img['flash_bytes']} / {img['ram_bytes']} B "
              f"| {faults} |")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
