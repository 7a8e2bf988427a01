"""Worst-case stack of each C entry point of neurov_c, from GCC's call graph.

Compile neurov_c's sources with -fcallgraph-info=su (the CI's cross-build
does), then

    python3 stack_usage.py build-m7/cpp/src/CMakeFiles/neurov_c.dir/*.ci

prints, for each neurov_* function, the largest sum of stack frames along any
call path below it, as GCC reports the frames. Functions outside the object
(sinf, cosf, expf, sqrtf, memcpy, memset from newlib) have no frame in the
graphs; each is counted with --external bytes (default 64, more than newlib's
float functions use on ARMv7-M). Fails if a frame is dynamic or the graph
has a cycle, since then there is no bound.
"""

import argparse
import re
import sys


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("graph", nargs="+",
                        help="the .ci files written by -fcallgraph-info=su (one per source; "
                             "a function inline in several counts with its largest frame)")
    parser.add_argument("--external", type=int, default=64,
                        help="bytes assumed for a function outside the object")
    parser.add_argument("--entry", default=r"neurov_\w+",
                        help="regular expression of the functions to report (default: the C interface's); "
                             "the processor-in-the-loop image asks for Reset_Handler and its interrupt handlers")
    args = parser.parse_args()

    text = "".join(open(g, encoding="utf-8").read() for g in args.graph)
    frame, kind = {}, {}
    for m in re.finditer(r'node: \{ title: "([^"]+)" label: "([^"]*)"', text):
        title, label = m.group(1), m.group(2)
        b = re.search(r"(\d+) bytes \((\w+)\)", label)
        if b is None:  # called here, defined elsewhere (or outside neurov_c)
            if title not in kind:
                frame[title], kind[title] = args.external, "external"
            continue
        if kind.get(title) in (None, "external") or int(b.group(1)) > frame[title]:
            frame[title], kind[title] = int(b.group(1)), b.group(2)
    calls = {}
    for m in re.finditer(r'edge: \{ sourcename: "([^"]+)" targetname: "([^"]+)"', text):
        if m.group(2) not in calls.setdefault(m.group(1), []):
            calls[m.group(1)].append(m.group(2))

    dynamic = [t for t, k in kind.items() if k not in ("static", "external")]
    if dynamic:
        print("frames that are not static (no bound):", *dynamic, sep="\n  ")
        return 1

    memo = {}

    def depth(node, path):
        if node in path:
            raise RecursionError(" -> ".join(path + (node,)))
        if node not in memo:
            below = [depth(c, path + (node,)) for c in calls.get(node, [])]
            memo[node] = frame.get(node, args.external) + max(below, default=0)
        return memo[node]

    entries = sorted(t for t in frame if re.fullmatch(args.entry, t))
    if not entries:
        print(f"no function matching {args.entry!r} in", *args.graph)
        return 1
    try:
        for name in entries:
            print(f"{name:32s} {depth(name, ()):6d} bytes")
    except RecursionError as cycle:
        print("recursion, no bound:", cycle)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
