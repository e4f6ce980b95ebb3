"""What a user waits for: the whole ``lubelink sweep`` command, on each executor, against serial simulate().

The sweep (issue 38): the ``paper`` scenario over ``film.viscosity`` x ``film.clearance``, two stored
quantities (``peak_u2_mid``, ``min_film``), 400 and 2,000 points (10,000 with ``--large``). Each size
is run as ``python -m lubelink sweep FILE -o OUT.zarr -q --executor E`` (a new process: imports,
kernels loaded from Numba's cache, validation, the store, the executor's start and stop), for
each executor of ``--executors``, timed from outside. Printed:

* wall time and points/s of each command;
* per executor, a least-squares line ``wall = fixed + marginal x points`` over the sizes: the
  fixed cost [s] and the marginal cost per point [ms];
* the same points as ``lubelink.simulate()`` calls in one warm process (a sample of them, scaled
  to each size), and the integration alone (``Run.wall_time``): the integration limit on two
  cores is ``2 / t_integration`` points/s (issue 38's target: 0.85x of it);
* the issue's targets: 400 points <= 2 s, 10,000 points <= 20 s.

The machine this runs on is shared and its speed varies: compare the ratios of one run.

Usage::

    python benchmarks/sweep_command.py                       # 400 and 2,000 points, 4 executors
    python benchmarks/sweep_command.py --large               # and 10,000 points
    python benchmarks/sweep_command.py --executors auto,processes --sizes 400,2000
"""

from __future__ import annotations

import argparse
import os
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

SWEEP = """base = "paper"
[vary]
"film.viscosity" = {{ start = 0.1, stop = 0.2, num = {a} }}
"film.clearance" = {{ start = 2e-3, stop = 3e-3, num = {b} }}
[store]
quantities = ["peak_u2_mid", "min_film"]
"""
GRIDS = {400: (20, 20), 2000: (40, 50), 10000: (100, 100)}


def grid(n):
    if n in GRIDS:
        return GRIDS[n]
    a = int(round(n ** 0.5))
    if n % a:
        raise SystemExit(f"--sizes: {n} is not one of {sorted(GRIDS)} nor a square-ish product")
    return a, n // a


def command(folder, n, executor, workers, other=None):
    """Wall time [s] of one ``lubelink sweep`` process, how many points completed and on what.

    ``other``: the ``src`` folder of another checkout, whose ``lubelink sweep`` (without
    ``--executor``: one from before it) runs instead."""
    a, b = grid(n)
    toml = Path(folder) / f"s{n}.toml"
    from lubelink._files import atomic_path

    with atomic_path(toml) as tmp:
        Path(tmp).write_text(SWEEP.format(a=a, b=b))
    out = Path(folder) / f"s{n}-{executor}.zarr"
    cmd = [sys.executable, "-m", "lubelink", "sweep", str(toml), "-o", str(out), "-q",
           "--max-points", str(max(n, 100_000))] + ([] if other else ["--executor", executor])
    if workers and executor != "serial":
        cmd += ["--workers", str(workers)]
    env = {**os.environ, "PYTHONPATH": str(Path(other).resolve())} if other else None
    t0 = time.perf_counter()
    r = subprocess.run(cmd, capture_output=True, text=True, env=env)
    wall = time.perf_counter() - t0
    if r.returncode not in (0, 1):
        raise SystemExit(f"{' '.join(cmd)} failed:\n{r.stderr[-2000:]}")
    import json

    import zarr

    g = zarr.open_group(str(out), mode="r")
    status = g["status"][...].reshape(-1)
    runs = json.loads(g.attrs["runs"])
    shutil.rmtree(out)
    return wall, int((status == "complete").sum()), runs[-1].get("executor", "before")


def single_runs(n_sample):
    """Mean ``simulate()`` time [s] and mean integration time (``Run.wall_time``) over ``n_sample``
    points spread over the 2,000-point grid, warm, in this process."""
    import numpy as np

    import lubelink
    from lubelink.config import resolve
    from lubelink.simulate import run

    a, b = grid(2000)
    mus, hs = np.linspace(0.1, 0.2, a), np.linspace(2e-3, 3e-3, b)
    points = [(mus[i % a], hs[(7 * i) % b]) for i in range(n_sample)]
    configs = [resolve("paper", {"film.viscosity": float(m), "film.clearance": float(h)}) for m, h in points]
    for c in configs[:3]:
        lubelink.simulate(c)
    t0 = time.perf_counter()
    for c in configs:
        lubelink.simulate(c)
    simulate = (time.perf_counter() - t0) / len(configs)
    integration = float(np.mean([run(c).wall_time for c in configs]))
    return simulate, integration


def fit(sizes, walls):
    """``(fixed [s], marginal [s/point])`` of the least-squares line through ``(sizes, walls)``."""
    import numpy as np

    if len(sizes) < 2:
        return float("nan"), walls[0] / sizes[0]
    b, a = np.polyfit(np.asarray(sizes, float), np.asarray(walls, float), 1)
    return float(a), float(b)


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--sizes", default="400,2000", help="points per sweep (default 400,2000)")
    parser.add_argument("--large", action="store_true", help="add the 10,000-point sweep")
    parser.add_argument("--executors", default="auto,serial,processes,dask",
                        help="comma-separated --executor values (default auto,serial,processes,dask)")
    parser.add_argument("--workers", type=int, default=0, help="--workers of the commands (default: one per core)")
    parser.add_argument("--sample", type=int, default=200, help="points timed as single simulate() calls")
    parser.add_argument("--compare-with", metavar="SRC",
                        help="also run the lubelink sweep of another checkout's src folder (an older one: "
                             "its default executor), a row 'before'")
    args = parser.parse_args(argv)
    sizes = [int(s) for s in args.sizes.split(",")] + ([10000] if args.large else [])
    executors = args.executors.split(",") + (["before"] if args.compare_with else [])
    print(f"paper, film.viscosity x film.clearance, 2 quantities; sizes {sizes}; {os.cpu_count()} cores; "
          f"load average {os.getloadavg()[0]:.2f} at start", flush=True)

    before = single_runs(args.sample)
    rows = {}
    with tempfile.TemporaryDirectory() as folder:
        for n in sizes:
            for e in executors:
                wall, complete, ran = command(folder, n, e, args.workers,
                                              args.compare_with if e == "before" else None)
                rows[(e, n)] = (wall, complete, ran)
                print(f"  {n:>6} points, --executor {e:<9} ({ran}): {wall:6.2f} s, {n / wall:6.0f} points/s, "
                      f"{complete} complete; load average {os.getloadavg()[0]:.2f}", flush=True)
    after = single_runs(args.sample)
    t_sim, t_int = 0.5 * (before[0] + after[0]), 0.5 * (before[1] + after[1])
    cores = min(2, os.cpu_count() or 1) if not args.workers else args.workers
    limit = cores / t_int

    print(f"\nsingle runs (mean of before and after): simulate() {1e3 * t_sim:.2f} ms, of which the integration "
          f"{1e3 * t_int:.2f} ms; integration limit on {cores} cores {limit:.0f} points/s")
    head = ["executor"] + [f"{n} pts [s]" for n in sizes] + [f"{n} pts/s" for n in sizes] + \
        ["fixed [s]", "marginal [ms/pt]", "marginal / limit"]
    table = [head]
    for e in executors:
        walls = [rows[(e, n)][0] for n in sizes]
        fixed, marginal = fit(sizes, walls)
        table.append([e] + [f"{w:.2f}" for w in walls] + [f"{n / w:.0f}" for n, w in zip(sizes, walls)]
                     + [f"{fixed:.2f}", f"{1e3 * marginal:.2f}", f"{(1 / marginal) / limit:.2f}"])
    table.append(["simulate() x n"] + [f"{n * t_sim:.2f}" for n in sizes] + [f"{1 / t_sim:.0f}" for _ in sizes]
                 + ["0", f"{1e3 * t_sim:.2f}", f"{(1 / t_sim) / limit:.2f}"])
    widths = [max(len(r[i]) for r in table) for i in range(len(head))]
    for i, r in enumerate(table):
        print("  ".join(c.ljust(w) for c, w in zip(r, widths)))
        if i == 0:
            print("  ".join("-" * w for w in widths))
    best = {n: min(rows[(e, n)][0] for e in executors) for n in sizes}
    if 400 in best:
        print(f"target 400 points <= 2 s: auto {rows.get(('auto', 400), (float('nan'),))[0]:.2f} s, "
              f"best {best[400]:.2f} s; ratio to 400 serial simulate() calls "
              f"{rows.get(('auto', 400), (float('nan'),))[0] / (400 * t_sim):.2f}")
    if 10000 in best:
        auto = rows.get(("auto", 10000), (float("nan"),))[0]
        print(f"target 10,000 points <= 20 s: auto {auto:.1f} s ({10000 / auto:.0f} points/s = "
              f"{10000 / auto / limit:.2f}x the integration limit; target 0.85x)")
    print(f"load average at end {os.getloadavg()[0]:.2f}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
