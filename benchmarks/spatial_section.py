"""The spatial model's cost: uniform against another checkout, and a tapered link against the uniform one.

Prints, for ``spatial-slider-crank`` (3 modes per direction unless ``--modes``):

1. with ``--compare-with PATH``: ``simulate()`` and the compiled ``spatial_rhs``, ``spatial_gap`` per
   call (in a compiled loop) of the uniform link, this checkout against the lubelink in
   ``PATH/src``: one warm process per checkout, asked in turn (A B A B ...), minimum of
   ``--repeats``, so that the shared machine's drifting speed cancels in the ratio;
2. in this checkout, the same three timings for a linear taper (``beam.width_ratio = 0.7``,
   ``beam.height_ratio = 1.3``: the three Galerkin eigenbases of ``lubelink.spatial_section``)
   beside the uniform link.

Times are wall-clock on a shared machine: compare ratios within one run, not across runs.

Usage::

    python benchmarks/spatial_section.py --compare-with /path/to/other/checkout --repeats 7
"""

from __future__ import annotations

import argparse
import os
import subprocess
import sys
from pathlib import Path

SNIPPET = """
import sys, time
import numpy as np
import numba
import lubelink
from lubelink.config import resolve
from lubelink.model import build_model
from lubelink.spatial_model import spatial_gap, spatial_rhs

@numba.njit
def loop_rhs(n, y, out, p):
    for i in range(n):
        spatial_rhs(0.1 + i * 1e-7, y, out, p)

@numba.njit
def loop_gap(n, y, p):
    for i in range(n):
        spatial_gap(0.1 + i * 1e-7, y, p)

cache = {}
print("ready", flush=True)
for line in sys.stdin:
    modes, ratio, what = line.split()
    over = {"beam.modes": int(modes)}
    if float(ratio) != 1.0:
        over.update({"beam.width_ratio": float(ratio), "beam.height_ratio": 2.0 - float(ratio)})
    key = (modes, ratio)
    if key not in cache:
        p = build_model(resolve("spatial-slider-crank", over)).params
        y = np.full(6 * int(modes), 1e-6)
        cache[key] = (p, y, np.empty_like(y))
        lubelink.simulate("spatial-slider-crank", over)
        loop_rhs(1, y, cache[key][2], p)
        loop_gap(1, y, p)
    p, y, out = cache[key]
    start = time.perf_counter()
    if what == "simulate":
        lubelink.simulate("spatial-slider-crank", over)
        print(time.perf_counter() - start, flush=True)
    elif what == "rhs":
        loop_rhs(20000, y, out, p)
        print((time.perf_counter() - start) / 20000, flush=True)
    else:
        loop_gap(20000, y, p)
        print((time.perf_counter() - start) / 20000, flush=True)
"""


def server(src):
    env = dict(os.environ, PYTHONPATH=str(src), LUBELINK_PREWARM="0")
    proc = subprocess.Popen([sys.executable, "-c", SNIPPET], env=env, stdin=subprocess.PIPE, stdout=subprocess.PIPE,
                            text=True)
    if proc.stdout.readline().strip() != "ready":
        raise RuntimeError(f"the lubelink in {src} did not start")
    return proc


def ask(proc, request):
    proc.stdin.write(request + "\n")
    proc.stdin.flush()
    return float(proc.stdout.readline())


def interleaved(procs, requests, repeats):
    """The minimum of ``repeats`` timings of each ``(proc, request)``, asked in turn; a first round warms up."""
    times = [[] for _ in requests]
    for _ in range(repeats + 1):
        for found, (proc, request) in zip(times, requests):
            found.append(ask(proc, request))
    return [min(found[1:]) for found in times]


def unit(what, v):
    return f"{1e3 * v:9.1f} ms" if what == "simulate" else f"{1e9 * v:9.0f} ns"


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--compare-with", metavar="PATH", help="a checkout of another lubelink version")
    parser.add_argument("--modes", type=int, default=3)
    parser.add_argument("--repeats", type=int, default=5)
    args = parser.parse_args(argv)
    here = server(Path(__file__).resolve().parents[1] / "src")
    procs = [here]
    try:
        if args.compare_with:
            other = server(Path(args.compare_with).resolve() / "src")
            procs.append(other)
            print(f"uniform spatial-slider-crank, {args.modes} modes: {args.compare_with} against this checkout "
                  f"(minimum of {args.repeats}, in turn)")
            print(f"{'what':<10}{'other':>14}{'this':>14}{'this/other':>12}")
            for what in ("simulate", "rhs", "gap"):
                request = f"{args.modes} 1.0 {what}"
                theirs, mine = interleaved(procs, [(other, request), (here, request)], args.repeats)
                print(f"{what:<10}{unit(what, theirs):>14}{unit(what, mine):>14}{mine / theirs:>11.3f}x")
        print(f"\nthis checkout, {args.modes} modes: tapered (width_ratio 0.7, height_ratio 1.3) against uniform")
        print(f"{'what':<10}{'uniform':>14}{'tapered':>14}{'ratio':>12}")
        for what in ("simulate", "rhs", "gap"):
            uni, tap = interleaved(procs, [(here, f"{args.modes} 1.0 {what}"), (here, f"{args.modes} 0.7 {what}")],
                                   args.repeats)
            print(f"{what:<10}{unit(what, uni):>14}{unit(what, tap):>14}{tap / uni:>11.3f}x")
    finally:
        for proc in procs:
            proc.stdin.close()
            proc.wait()


if __name__ == "__main__":
    main()
