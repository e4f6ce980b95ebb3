"""Cost of the two-way coupling of crank and link (lubelink.coupling) against the one-way driven crank and the
prescribed speed, and what the coupling changes: the crank speed's fluctuation, the peak mid-span deflection.

    PYTHONPATH=src python benchmarks/coupled_cost.py [scenario ...]
    PYTHONPATH=src python benchmarks/coupled_cost.py --long    (the link runs against t_end, whole and in windows)

Each configuration is run once to compile and load, then timed (best of ``REPEATS``). The drive: a constant
motor torque, a flywheel of ``J_f``, a slider of ``m_s`` (a driven scenario, ``driven-piston``: its own drive, one
way and two ways); ``solver.t_end`` of the scenario.
"""

import sys
import time

import numpy as np

from lubelink.config import resolve
from lubelink.simulate import run

REPEATS = 2
DRIVE = {"drive.law": "torque", "drive.flywheel_inertia": 0.1, "drive.slider_mass": 0.5}


def timed(config):
    run(config)
    best, result = np.inf, None
    for _ in range(REPEATS):
        start = time.perf_counter()
        result = run(config)
        best = min(best, time.perf_counter() - start)
    return best, result


def figures(result):
    N = result.model.modes
    mid = np.sin(np.arange(1, N + 1) * np.pi / 2)
    peak = float(np.abs(result.y[:, :N] @ mid).max())
    crank = getattr(result.model.motion, "crank", None)
    if crank is None:
        return peak, 0.0
    w = crank(result.t)[1]
    return peak, float((w.max() - w.min()) / np.mean(w))


def main(cases):
    print(f"{'scenario':<22}{'model':<11}{'time s':>9}{'x speed':>9}{'runs':>6}{'peak u2(L/2) m':>16}"
          f"{'fluct.':>9}{'1st change':>12}{'contraction':>13}")
    for scenario, sets in cases:
        rows = {"speed": {}, "one-way": DRIVE, "two-way": {**DRIVE, "drive.coupling": "two-way"}}
        if not resolve(scenario).drive.prescribed:  # a driven scenario: its own drive, one way and two ways
            rows = {"one-way": {"drive.coupling": "one-way"}, "two-way": {"drive.coupling": "two-way"}}
        base = None
        for name, extra in rows.items():
            cost, result = timed(resolve(scenario, {**sets, **extra}))
            base = cost if base is None else base
            peak, fluct = figures(result)
            rec = result.coupling
            runs = rec.runs if rec else 1
            first = f"{rec.changes[0]:.3g}" if rec else ""
            contraction = f"{rec.contraction:.3g}" if rec else ""
            label = scenario + (f" N={sets['beam.modes']}" if "beam.modes" in sets else "")
            print(f"{label:<22}{name:<11}{cost:>9.3f}{cost / base:>9.1f}{runs:>6}{peak:>16.4e}{fluct:>9.4f}"
                  f"{first:>12}{contraction:>13}")


def long_runs(ends=(0.5, 2.0, 5.0, 10.0)):
    """``paper-dry`` undamped, two-way: link runs, windows and wall time against ``t_end``, relaxed whole and in
    windows of ``coupling.WINDOW_TURNS`` turns (the default)."""
    from lubelink import coupling
    from lubelink.coupling import CouplingError

    windowed = coupling.WINDOW_TURNS
    print(f"{'t_end s':>8}{'relaxed':>10}{'time s':>9}{'runs':>6}{'windows':>9}{'runs/window':>13}{'last change':>13}")
    for t_end in ends:
        for name, turns in (("whole", 1e9), ("windows", windowed)):
            coupling.WINDOW_TURNS = turns
            config = resolve("paper-dry", {**DRIVE, "drive.coupling": "two-way", "solver.t_end": t_end})
            try:
                cost, result = timed(config)
            except CouplingError as exc:
                print(f"{t_end:>8.1f}{name:>10}  refused: {str(exc)[:90]}")
                continue
            rec = result.coupling
            per = max(len(c) for _, c in rec.windows) if rec.windows else rec.runs
            print(f"{t_end:>8.1f}{name:>10}{cost:>9.3f}{rec.runs:>6}{len(rec.windows) or 1:>9}{per:>13}"
                  f"{rec.changes[-1]:>13.3g}")
    coupling.WINDOW_TURNS = windowed


if __name__ == "__main__":
    if sys.argv[1:] == ["--long"]:
        long_runs()
        sys.exit()
    names = sys.argv[1:] or ["paper-dry", "paper", "driven-piston"]
    main([(n, {}) for n in names] + ([("paper-dry", {"beam.modes": 5})] if not sys.argv[1:] else []))
