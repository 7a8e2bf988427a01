"""One colour per controller, the same in every figure of a study (box plot
and error bands) and from study to study for the shipped controllers' names.

Grey is kept out: a band figure draws the other controllers' medians in grey,
so a controller drawn grey (or black, the desired path's colour in the run
plots) would read as "the others".
"""

from __future__ import annotations

from collections.abc import Sequence

from matplotlib.colors import to_hex

__all__ = ["OTHERS_GREY", "PALETTE", "controller_colours"]

#: The colour of the other controllers' medians in a band figure.
OTHERS_GREY = "0.8"

#: Distinct colours, none grey: tab10 without its grey, then the dark shades
#: of tab20b/tab20c, which stay apart from tab10's hues.
PALETTE = ("#1f77b4", "#ff7f0e", "#2ca02c", "#d62728", "#9467bd", "#8c564b", "#e377c2",
           "#bcbd22", "#17becf", "#393b79", "#637939", "#8c6d31", "#7b4173", "#3182bd",
           "#e6550d", "#31a354", "#756bb1", "#843c39")

#: The shipped studies' controller names (python/neurov/studies/*.toml), each
#: with its own palette entry so that "NN adaptive" has one colour in every study.
_KNOWN = {"pd": 0, "pid": 1, "smc": 2, "linear": 3, "linear_nominal": 4, "computed_torque": 5,
          "nn": 6, "nn_sigma": 7, "nn_emod": 8, "nn_projection": 9, "nn_dead_zone": 10,
          "super_twisting": 11, "ardusub": 12}


def controller_colours(names: Sequence[str]) -> dict[str, str]:
    """A distinct colour (hex) for each controller name in `names`: the shipped
    names keep their own, any other takes the first palette colour that no
    controller of `names` has; past the palette, evenly spaced hues."""
    names = list(names)
    if len(set(names)) != len(names):
        raise ValueError(f"argument 'names' must not repeat a controller, got {names}")
    taken = {_KNOWN[n] for n in names if n in _KNOWN}
    free = (i for i in range(len(PALETTE)) if i not in taken)
    out: dict[str, str] = {}
    extra = [n for n in names if n not in _KNOWN]
    for n in names:
        if n in _KNOWN:
            out[n] = PALETTE[_KNOWN[n]]
    spill = []
    for n in extra:
        i = next(free, None)
        if i is None:
            spill.append(n)
        else:
            out[n] = PALETTE[i]
    if spill:
        from matplotlib import colormaps

        # Hues between the palette's: "hsv" never passes through grey.
        cmap = colormaps["hsv"]
        for k, n in enumerate(spill):
            out[n] = to_hex(cmap((k + 0.5) / len(spill) * 0.9))
    return {n: out[n] for n in names}
