"""Cost of the finite-width film: one right-hand side, and the ``paper`` scenario over 2 s, per ``film.reynolds``.

    PYTHONPATH=src python benchmarks/film2d_cost.py [--evaluations 20000]

Prints, for ``film.reynolds`` = 1d, short, 2d (and 2d clipped by half-Sommerfeld, 2d with more
terms or a finer pad grid): the time of one compiled right-hand side (``model.rhs`` called in a
compiled loop, so the dispatch from Python is not counted; median of 5 loops), and
``lubelink.simulate("paper")`` over 0-2 s (median of 3 warm runs) with its evaluations. The first
call of each configuration compiles and is not timed. Times are wall-clock on a shared machine:
compare ratios within one run.
"""

from __future__ import annotations

import argparse
import statistics
import time

import numpy as np

import lubelink
from lubelink.config import resolve
from lubelink.link.model import rhs
from lubelink.build import build_model

CASES = [
    ("1d", {}),
    ("short", {"film.reynolds": "short"}),
    ("2d", {"film.reynolds": "2d"}),
    ("2d, 16 sine terms", {"film.reynolds": "2d", "film.width_series": "sine", "film.width_modes": 16}),
    ("2d, grid 401", {"film.reynolds": "2d", "film.grid_points": 401}),
    ("2d, half-Sommerfeld", {"film.reynolds": "2d", "film.cavitation": "half-sommerfeld"}),
    ("1d, Swift-Stieber", {"film.cavitation": "reynolds"}),
]


def _loop():
    import numba

    @numba.njit
    def many(t, y, out, p, n):
        for i in range(n):
            rhs(t + 1e-6 * i, y, out, p)
        return out[0]

    return many


def per_rhs(settings, evaluations, many):
    model = build_model(resolve("paper", settings))
    y = np.array([1e-3, 2e-3])
    out = np.empty(2)
    many(0.3, y, out, model.params, 10)  # compile
    times = []
    for _ in range(5):
        began = time.perf_counter()
        many(0.3, y, out, model.params, evaluations)
        times.append((time.perf_counter() - began) / evaluations)
    return statistics.median(times)


def paper_run(settings):
    lubelink.simulate("paper", set=settings)  # compile / warm
    times, ds = [], None
    for _ in range(3):
        began = time.perf_counter()
        ds = lubelink.simulate("paper", set=settings)
        times.append(time.perf_counter() - began)
    return statistics.median(times), ds


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--evaluations", type=int, default=20000)
    args = parser.parse_args()
    many = _loop()
    print("| film | one rhs [µs] | paper 0-2 s [s] | rhs evaluations | peak force [N] |")
    print("|---|---|---|---|---|")
    for name, settings in CASES:
        cost = per_rhs(settings, args.evaluations, many)
        wall, ds = paper_run(settings)
        print(f"| {name} | {cost * 1e6:.2f} | {wall:.3f} | {ds.attrs['nfev']} "
              f"| {float(np.abs(ds.film_force).max()):.4g} |", flush=True)


if __name__ == "__main__":
    main()
