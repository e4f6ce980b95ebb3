"""Every method on every backend through ``paper-impact``: status, impacts and their times.

``python tools/method_matrix.py`` runs the ``paper-impact`` scenario (1 mode, 0-2 s, restitution
impacts and sustained contact) with each integration method, backend and relative tolerance and
compares each run's impact sequence with a reference: SciPy's Radau and the compiled DOP853 at
tolerances far below those of the matrix, which must agree with each other first. It prints, per run,
the status, the number of impacts, the largest difference of an impact time from the reference
(over the impacts both have) and the wall time: the table of docs/reliability.md.
"""

from __future__ import annotations

import argparse
import time
from concurrent.futures import ProcessPoolExecutor

import numpy as np

SCENARIO = "paper-impact"


def impacts(method, backend, rtol, atol=None, t_end=2.0):
    """``(status, impact times, wall time [s])`` of one run."""
    from lubelink.config import resolve
    from lubelink.simulate import run

    settings = {"solver.method": method, "solver.backend": backend, "solver.rtol": rtol,
                "solver.atol": atol if atol is not None else rtol * 1e-3, "solver.t_end": t_end}
    t0 = time.perf_counter()
    r = run(resolve(SCENARIO, settings))
    return r.status, np.array([i[0] for i in r.impacts]), time.perf_counter() - t0


def _row(args):
    return args, impacts(*args)


def main(argv=None):
    from lubelink import integrate

    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--rtol", type=float, nargs="*", default=[1e-6, 1e-8, 1e-10])
    parser.add_argument("--methods", nargs="*", default=list(integrate.METHODS))
    parser.add_argument("--backends", nargs="*", default=["numba", "numpy"])
    parser.add_argument("--t-end", type=float, default=2.0)
    parser.add_argument("--workers", type=int, default=2)
    args = parser.parse_args(argv)

    radau = impacts("Radau", "numba", 1e-11, 1e-15, args.t_end)
    dop = impacts("DOP853", "numba", 1e-12, 1e-16, args.t_end)
    n = min(radau[1].size, dop[1].size)
    print(f"reference: Radau rtol 1e-11 {radau[0]}, {radau[1].size} impacts; DOP853 rtol 1e-12 {dop[0]}, "
          f"{dop[1].size} impacts; largest difference {1e6 * np.max(np.abs(radau[1][:n] - dop[1][:n])):.3g} us")
    reference = radau[1]
    jobs = [(m, b, rtol, None, args.t_end) for rtol in args.rtol for m in args.methods for b in args.backends]
    print("| method | backend | rtol | status | impacts | largest difference [us] | wall [s] |")
    print("|---|---|---|---|---|---|---|")
    with ProcessPoolExecutor(args.workers) as pool:
        for (m, b, rtol, _, _), (status, times, wall) in pool.map(_row, jobs):
            k = min(times.size, reference.size)
            worst = np.max(np.abs(times[:k] - reference[:k])) if k else np.nan
            print(f"| {m} | {b} | {rtol:g} | {status} | {times.size} | {1e6 * worst:.3g} | {wall:.2f} |", flush=True)


if __name__ == "__main__":
    main()
