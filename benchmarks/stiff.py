"""The stiff-film regime: a real clearance, many modes, the stiff method against the others.

The case of issue 33: scenario ``lubricated`` with ``film.clearance = 1e-4`` (the squeeze film
damps at 2.6e6 1/s) and ``contact.law = "compliant"``, 2 s simulated. Prints, in one run:

* ``simulate()`` end to end (warm, median of ``--repeats``) with ``solver.method = "auto"`` (which
  takes RODAS4 with the analytic Jacobian here) for 15, 31 and 63 modes, its steps and evaluations;
* RODAS4 with the Jacobian by finite differences (the fallback), 15 modes;
* the previous default (the exponential Runge-Kutta method) and SciPy's Radau (finite-difference
  Jacobian; the same compiled right-hand side, the method run as Python) on ``--short`` seconds, scaled to 2 s (both take minutes for 2 s);
* the accuracy at the default tolerance: the largest difference of ``u2_mid`` and of the thinnest
  film to RODAS4 at rtol 1e-10, atol 1e-13;
* the spatial link (``spatial-slider-crank``, a squeeze film at 40 um, 3 modes in each direction,
  0.1 s): "auto" (RODAS4 with the spatial Jacobian) against the exponential method and SciPy's Radau.

Usage::

    python benchmarks/stiff.py                      # about 5 minutes on 2 cores
    python benchmarks/stiff.py --modes 15 --repeats 1 --short 0.02
"""

from __future__ import annotations

import argparse
import statistics
import time

import numpy as np

CASE = "lubricated"
BASE = {"film.clearance": 1e-4, "contact.law": "compliant", "solver.t_end": 2.0}


def timed(settings, repeats, case=CASE):
    """``(median seconds, dataset)`` of warm ``simulate()`` calls."""
    import lubelink

    lubelink.simulate(case, set=settings)  # compile or load the kernels, warm the caches
    times, ds = [], None
    for _ in range(repeats):
        t0 = time.perf_counter()
        ds = lubelink.simulate(case, set=settings)
        times.append(time.perf_counter() - t0)
    return statistics.median(times), ds


def row(label, seconds, ds, scale=1.0):
    a = ds.attrs
    print(f"{label:<44} {seconds * scale:9.3f} s {a['nsteps'] * scale:11.0f} {a['nfev'] * scale:12.0f}  "
          f"{a['solver_method']}, {a['status']}")


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--modes", default="15,31,63", help="numbers of modes for the auto (stiff) runs")
    ap.add_argument("--repeats", type=int, default=3)
    ap.add_argument("--short", type=float, default=0.05, help="interval [s] of the slow methods' runs, scaled to 2 s")
    args = ap.parse_args()
    modes = [int(m) for m in args.modes.split(",")]
    print(f"{CASE}, clearance 1e-4 m, compliant contact, 2 s simulated; simulate() end to end, warm")
    print(f"{'run':<44} {'wall':>11} {'steps':>11} {'evaluations':>12}  method, status")
    fast = {}
    for n in modes:
        seconds, ds = timed({**BASE, "beam.modes": n}, args.repeats)
        fast[n] = seconds
        row(f"{n} modes, auto", seconds, ds)
        if n == modes[0]:
            print(f"{'':<44} ({ds.attrs['solver_note']})")
    n = modes[0]
    seconds, ds = timed({**BASE, "beam.modes": n, "film.cavitation": "reynolds"}, 1)
    row(f"{n} modes, rodas, Reynolds cavitation (FD Jacobian)", seconds, ds)
    print(f"{'':<44} ({ds.attrs['solver_note']})")
    scale = BASE["solver.t_end"] / args.short
    short = {**BASE, "beam.modes": n, "solver.t_end": args.short}
    s_rodas, ds = timed({**short}, args.repeats)
    row(f"{n} modes, rodas, {args.short:g} s x {scale:g}", s_rodas, ds, scale)
    s_exp, ds = timed({**short, "solver.method": "exponential"}, 1)
    row(f"{n} modes, exponential, {args.short:g} s x {scale:g}", s_exp, ds, scale)
    s_radau, ds = timed({**short, "solver.method": "Radau"}, 1)
    row(f"{n} modes, SciPy Radau, {args.short:g} s x {scale:g}", s_radau, ds, scale)
    print(f"ratios on the same {args.short:g} s: exponential / rodas {s_exp / s_rodas:.0f}x, "
          f"SciPy Radau / rodas {s_radau / s_rodas:.0f}x")
    if n in fast:
        s_full, ds = timed({**BASE, "beam.modes": n, "solver.method": "Radau"}, 1)
        row(f"{n} modes, SciPy Radau, 2 s", s_full, ds)
        print(f"ratio on the whole 2 s: SciPy Radau / rodas {s_full / fast[n]:.1f}x (the first "
              f"{args.short:g} s, a transient, favour rodas)")

    import lubelink

    print("accuracy at the default tolerance against rodas at rtol 1e-10, atol 1e-13 (2 s):")
    for m in modes[:2]:
        ref = lubelink.simulate(CASE, set={**BASE, "beam.modes": m, "solver.method": "rodas", "solver.rtol": 1e-10,
                                           "solver.atol": 1e-13})
        run = lubelink.simulate(CASE, set={**BASE, "beam.modes": m})
        du = float(np.abs(run.u2_mid - ref.u2_mid).max()) * 1e6
        dh = float(np.abs(run.film_min - ref.film_min).max()) * 1e6
        print(f"  {m} modes: u2_mid {du:.4f} um, thinnest film {dh:.4f} um "
              f"(peak |u2_mid| {float(np.abs(ref.u2_mid).max()) * 1e3:.4f} mm)")
    for n, target in ((15, 1.0), (31, 2.0), (63, 10.0)):
        if n in fast:
            print(f"target {n} modes <= {target:g} s: {fast[n]:.3f} s, {'met' if fast[n] <= target else 'not met'}")


def spatial(repeats):
    """The spatial link with a stiff squeeze film: auto (rodas) against the exponential method and Radau."""
    base = {"film.model": "wedge+squeeze", "film.clearance": 4e-5, "film.viscosity": 0.05, "solver.t_end": 0.1,
            "contact.law": "none", "beam.modes": 3}
    print("spatial-slider-crank, squeeze film at 40 um, 3 modes a direction, 0.1 s; simulate() end to end, warm")
    results = {}
    for label, method, n in (("auto", "auto", repeats), ("exponential", "exponential", 1), ("SciPy Radau", "Radau", 1)):
        seconds, ds = timed({**base, "solver.method": method}, n, "spatial-slider-crank")
        results[label] = (seconds, ds)
        row(f"spatial, {label}", seconds, ds)
    ref = results["SciPy Radau"][1]
    for label in ("auto", "exponential"):
        seconds, ds = results[label]
        du = max(float(np.abs(ds[v] - ref[v]).max()) for v in ("u2_mid", "u3_mid"))
        print(f"  {label}: {results['SciPy Radau'][0] / seconds:.1f}x Radau's speed, |u - u_Radau| <= {du:.2g} m")


if __name__ == "__main__":
    main()
    spatial(3)
