"""Work-precision diagrams: error against wall time of each compiled method, 1 to 15 modes, dry, film, impacts.

For each case (``paper-dry``: the link alone; ``paper``: the lubricated joint; ``paper-impact``: film
breakdown with impacts), each number of modes and each method (DOP853, the exponential
Runge-Kutta method, the exponential Adams method, Bulirsch-Stoer), the integration (``lubelink.simulate.run``, warm, median of
``--repeats``) is timed at tolerances ``rtol = 10 atol`` from 1e-5 to 1e-10 and at the scenario's
own tolerances (the defaults rtol 1e-6, atol 1e-8; ``paper-impact`` pins 1e-8, 1e-9). The error is the largest difference of the midpoint deflection ``u2_mid`` over the run
to a DOP853 run at rtol 1e-12, atol 1e-15. Runs that stop early (film breakdown, chatter) are
compared on the samples they have, and marked.

``paper-impact`` is integrated only up to :data:`AFTER_IMPACT` after the reference's first impact.
With more than one mode its impacts come in sequences (38-82 impacts in 2 s with 3 modes) that
depend sensitively on the state: runs at rtol 1e-10 and 1e-12 agree within 1 µm only up to
1.47 s, at 1e-11 and 1e-12 up to 1.58 s, so an error over the whole run measures that
sensitivity, not the method (every method, at every tolerance, ends 1-20 mm from the reference).
The first impact and its aftermath are a convergent measure.

Prints one table row per run and draws ``benchmarks/work_precision.png`` (one panel per case and
number of modes; the scenario's own tolerances circled).

Usage::

    python benchmarks/work_precision.py                 # about 15 minutes on 2 cores
    python benchmarks/work_precision.py --modes 1,7 --repeats 1 --output /tmp/wp.png
"""

from __future__ import annotations

import argparse
import statistics
import time
from pathlib import Path

import numpy as np

CASES = ("paper-dry", "paper", "paper-impact")
METHODS = ("DOP853", "exponential", "exponential-adams", "bulirsch-stoer")
RTOLS = (1e-5, 1e-6, 1e-7, 1e-8, 1e-9, 1e-10)
DEFAULT = "default"  # the rtol column of the run at the scenario's own tolerances
TIGHT = {"solver.method": "DOP853", "solver.rtol": 1e-12, "solver.atol": 1e-15}
#: ``paper-impact`` ends this long after the reference's first impact [s] (see the module docstring).
AFTER_IMPACT = 0.05


def u2_mid(run):
    from lubelink import beam

    L = run.model.config.mechanism.rod_length
    return beam.deflection(run.y[:, :run.model.modes], np.array([0.5 * L]), L)[:, 0]


def measure(case, modes, repeats):
    """Rows ``(method, rtol, seconds, error, nfev, status)`` of one case."""
    from lubelink.config import resolve
    from lubelink.simulate import run

    common = {"beam.modes": modes}
    tight = run(resolve(case, {**common, **TIGHT, "solver.max_wall_time": 120.0}))
    if case == "paper-impact" and tight.impacts:
        common["solver.t_end"] = tight.impacts[0][0] + AFTER_IMPACT
        tight = run(resolve(case, {**common, **TIGHT}))
    ref = u2_mid(tight)
    rows = []
    for method in METHODS:
        for rtol in RTOLS + (DEFAULT,):
            tolerances = {} if rtol == DEFAULT else {"solver.rtol": rtol, "solver.atol": rtol / 10}
            config = resolve(case, {**common, "solver.method": method, **tolerances})
            r = run(config)
            times = []
            for _ in range(repeats):
                start = time.perf_counter()
                r = run(config)
                times.append(time.perf_counter() - start)
            n = min(len(r.t), len(tight.t))
            err = float(np.max(np.abs(u2_mid(r)[:n] - ref[:n])))
            rows.append((method, rtol, statistics.median(times), err, r.nfev, r.status))
    return rows, tight.status


def draw(results, modes_list, path):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.ticker import FuncFormatter, LogLocator, NullFormatter

    fig, axes = plt.subplots(len(CASES), len(modes_list), figsize=(3.2 * len(modes_list), 2.8 * len(CASES)),
                             squeeze=False, sharey=True)
    colours = dict(zip(METHODS, ("C0", "C3", "C1", "C2")))
    for i, case in enumerate(CASES):
        for j, modes in enumerate(modes_list):
            ax = axes[i, j]
            rows = results[case, modes]
            for method in METHODS:
                mine = [r for r in rows if r[0] == method]
                t = [1e3 * r[2] for r in mine]
                e = [max(r[3], 1e-13) for r in mine]
                line = [k for k, r in enumerate(mine) if r[1] != DEFAULT]
                ax.loglog([t[k] for k in line], [e[k] for k in line], "o-", ms=3, color=colours[method], label=method)
                for r, ti, ei in zip(mine, t, e):
                    if r[1] == DEFAULT:
                        ax.plot(ti, ei, "o", ms=9, mfc="none", color=colours[method])
                    if r[5] != "complete":
                        ax.plot(ti, ei, "x", ms=7, color="k")
            title = f"{case}, {modes} mode{'s' if modes > 1 else ''}"
            if case == "paper-impact":
                title += f", to impact 1 + {1e3 * AFTER_IMPACT:.0f} ms"
            ax.set_title(title, fontsize=8)
            ax.xaxis.set_major_locator(LogLocator(subs=(1.0, 2.0, 5.0)))
            ax.xaxis.set_major_formatter(FuncFormatter(lambda v, _: f"{v:g}"))
            ax.xaxis.set_minor_formatter(NullFormatter())
            ax.grid(True, which="both", lw=0.3)
            if i == len(CASES) - 1:
                ax.set_xlabel("integration time [ms]")
            if j == 0:
                ax.set_ylabel("max |u2_mid error| [m]")
    axes[0, 0].legend(fontsize=7)
    fig.suptitle("Work-precision: rtol = 10 atol from 1e-5 to 1e-10; circled: the scenario's tolerances "
                 "(default rtol 1e-6, atol 1e-8); x: stopped early", fontsize=9)
    fig.tight_layout()
    from lubelink._files import atomic_path

    path = Path(path)
    with atomic_path(path) as tmp:
        fig.savefig(tmp, dpi=110)
    print(f"\nwrote {path}")


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--modes", default="1,3,7,15", help="comma-separated numbers of modes")
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--output", default=str(Path(__file__).with_name("work_precision.png")))
    args = parser.parse_args(argv)
    modes_list = [int(m) for m in args.modes.split(",")]
    results = {}
    print(f"{'case':<14}{'modes':>5} {'method':<16}{'rtol':>8}{'time [ms]':>11}{'error [m]':>11}{'nfev':>9}  status")
    for case in CASES:
        for modes in modes_list:
            rows, tight_status = measure(case, modes, args.repeats)
            results[case, modes] = rows
            for method, rtol, seconds, err, nfev, status in rows:
                shown = f"{rtol:>8}" if rtol == DEFAULT else f"{rtol:>8.0e}"
                print(f"{case:<14}{modes:>5} {method:<16}{shown}{1e3 * seconds:>11.2f}{err:>11.2e}{nfev:>9}  "
                      f"{status}")
            if tight_status != "complete":
                print(f"   (the reference run stopped early: {tight_status})")
    draw(results, modes_list, args.output)


if __name__ == "__main__":
    main()
