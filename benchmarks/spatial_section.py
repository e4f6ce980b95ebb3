"""The spatial model's cost: uniform against another checkout, and a tapered link against the uniform one.

Prints, for ``spatial-slider-crank`` (3 modes per direction unless ``--modes``):

1. with ``--compare-with PATH``: ``simulate()`` and the compiled ``spatial_rhs``, ``spatial_gap`` per
   call (in a compiled loop) of the uniform link, this checkout against the lubelink in
   ``PATH/src``: one warm process per checkout, asked in turn (A B A B ...), minimum of
   ``--repeats``, so that the shared machine's drifting speed cancels in the ratio;
2. in this checkout, the same three timings for a linear taper (``beam.width_ratio = 0.7``,
   ``beam.height_ratio = 1.3``: the three Galerkin eigenbases of ``lubelink.link.spatial_section``)
   beside the uniform link.

Times are wall-clock on a shared machine: compare ratios within one run, not across runs.

Usage::

    python benchmarks/spatial_section.py --compare-with /path/to/other/checkout --repeats 7
"""

from __future__ import annotations

import argparse
from pathlib import Path

from bench import interleaved, servers  # the paired warm processes of bench.py (this folder)

TAPER = "beam.width_ratio=0.7 beam.height_ratio=1.3"


def unit(what, v):
    return f"{1e3 * v:9.1f} ms" if what == "simulate" else f"{1e9 * v:9.0f} ns"


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--compare-with", metavar="PATH", help="a checkout of another lubelink version")
    parser.add_argument("--modes", type=int, default=3)
    parser.add_argument("--repeats", type=int, default=5)
    args = parser.parse_args(argv)
    sources = [Path(__file__).resolve().parents[1] / "src"]
    if args.compare_with:
        sources.append(Path(args.compare_with).resolve() / "src")
    procs = servers(sources)
    here = procs[0]
    case = f"spatial-slider-crank {args.modes}"
    try:
        if args.compare_with:
            other = procs[1]
            print(f"uniform spatial-slider-crank, {args.modes} modes: {args.compare_with} against this checkout "
                  f"(minimum of {args.repeats}, in turn)")
            print(f"{'what':<10}{'other':>14}{'this':>14}{'this/other':>12}")
            for what in ("simulate", "rhs", "gap"):
                request = f"{case} {what}"
                theirs, mine = interleaved([(other, request), (here, request)], args.repeats)
                print(f"{what:<10}{unit(what, theirs):>14}{unit(what, mine):>14}{mine / theirs:>11.3f}x")
        print(f"\nthis checkout, {args.modes} modes: tapered (width_ratio 0.7, height_ratio 1.3) against uniform")
        print(f"{'what':<10}{'uniform':>14}{'tapered':>14}{'ratio':>12}")
        for what in ("simulate", "rhs", "gap"):
            uni, tap = interleaved([(here, f"{case} {what}"), (here, f"{case} {what} {TAPER}")], args.repeats)
            print(f"{what:<10}{unit(what, uni):>14}{unit(what, tap):>14}{tap / uni:>11.3f}x")
    finally:
        for proc in procs:
            proc.stdin.close()
            proc.wait()


if __name__ == "__main__":
    main()
