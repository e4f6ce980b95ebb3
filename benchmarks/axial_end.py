"""The cost of the spatial link's axial end condition (``beam.axial_end``): free against fixed, and fixed against
another checkout.

Prints, for ``spatial-slider-crank`` (uniform link; ``--modes``, default 1 3 7 per direction) and its tapered
variant (``beam.width_ratio = 0.7``, ``beam.height_ratio = 1.3``: the eigenbases), ``simulate()`` and the
compiled ``spatial_rhs`` per call (in a compiled loop) with the fixed and the free end, in one warm process
asked in turn (A B A B ...), minimum of ``--repeats``; with ``--compare-with PATH`` also the lubelink in
``PATH/src`` (a checkout before the key: its fixed end) in a second warm process, in the same turns.

Times are wall-clock on a shared machine: compare ratios within one run, not across runs.

Usage::

    python benchmarks/axial_end.py --compare-with /path/to/other/checkout --repeats 7
"""

from __future__ import annotations

import argparse
from pathlib import Path

from bench import interleaved, servers  # the paired warm processes of bench.py (this folder)

TAPER = "beam.width_ratio=0.7 beam.height_ratio=1.3"


def unit(what, v):
    return f"{1e3 * v:9.2f} ms" if what == "simulate" else f"{1e9 * v:9.0f} ns"


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--compare-with", metavar="PATH", help="a checkout of lubelink before beam.axial_end")
    parser.add_argument("--modes", type=int, nargs="+", default=[1, 3, 7])
    parser.add_argument("--repeats", type=int, default=5)
    args = parser.parse_args(argv)
    sources = [Path(__file__).resolve().parents[1] / "src"]
    if args.compare_with:
        sources.append(Path(args.compare_with).resolve() / "src")
    procs = servers(sources)
    here = procs[0]
    head = f"{'case':<22}{'what':<10}" + (f"{'before':>12}" if args.compare_with else "") + \
        f"{'fixed':>12}{'free':>12}{'free/fixed':>12}" + (f"{'fixed/before':>14}" if args.compare_with else "")
    print(f"spatial-slider-crank, minimum of {args.repeats}, in turn\n{head}")
    try:
        for modes in args.modes:
            for label, extra in (("uniform", ""), ("taper", TAPER)):
                for what in ("simulate", "rhs"):
                    case = f"spatial-slider-crank {modes} {what} {extra}".strip()
                    requests = [(here, f"{case} beam.axial_end=fixed"), (here, f"{case} beam.axial_end=free")]
                    if args.compare_with:
                        requests.append((procs[1], case))
                    found = interleaved(requests, args.repeats)
                    fixed, free = found[:2]
                    row = f"{label + ' ' + str(modes) + ' modes':<22}{what:<10}"
                    if args.compare_with:
                        row += f"{unit(what, found[2]):>12}"
                    row += f"{unit(what, fixed):>12}{unit(what, free):>12}{free / fixed:>11.3f}x"
                    if args.compare_with:
                        row += f"{fixed / found[2]:>13.3f}x"
                    print(row, flush=True)
    finally:
        for proc in procs:
            proc.stdin.close()
            proc.wait()


if __name__ == "__main__":
    main()
