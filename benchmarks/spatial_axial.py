"""The spatial link's axial force (``beam.model = "spatial"``, ``beam.axial_force = "inertial"``): what it changes
and what it costs.

Prints, over ``--t-end`` (default 2 s) with ``--modes`` modes per direction:

* the planar case (``paper-dry``): the largest ``u2_mid`` difference between the spatial and the planar model with
  each setting of ``beam.axial_force`` (both with the geometric stiffness and the chord's rotation under the slider
  with ``"inertial"``; what remains is the spatial link's axial coupling), and the largest ``|u3_mid|`` (0: the
  plane is kept);
* ``spatial-slider-crank`` (a tilted crank, an offset slider line): the peaks of ``u2_mid``, ``u3_mid`` with each
  setting and the largest change the axial force makes;
* warm ``simulate`` wall times of both scenarios with each setting, median of ``--repeats``, and the right-hand
  sides the run took (``nfev``; run with
  ``LUBELINK_FIRST_RUN=compile`` so that the first call compiles). Wall-clock on a shared machine: compare the
  ratio within one run.

    python benchmarks/spatial_axial.py --modes 5 --repeats 5
"""

from __future__ import annotations

import argparse
import statistics
import time

import numpy as np

SETTINGS = ("none", "inertial")


def run(scenario, sets):
    import lubelink

    ds = lubelink.simulate(scenario, sets)
    if ds.attrs["status"] != "complete":
        raise SystemExit(f"{scenario} {sets}: {ds.attrs['status']}")
    return ds


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--modes", type=int, default=5)
    parser.add_argument("--t-end", type=float, default=2.0)
    parser.add_argument("--repeats", type=int, default=5)
    args = parser.parse_args(argv)
    base = {"beam.modes": args.modes, "solver.t_end": args.t_end}
    print(f"planar case (paper-dry, {args.modes} modes, 0-{args.t_end:g} s): spatial against planar")
    for a in SETTINGS:
        pl = run("paper-dry", {**base, "beam.axial_force": a})
        sp = run("paper-dry", {**base, "beam.axial_force": a, "beam.model": "spatial"})
        d = np.abs(sp.u2_mid.values - pl.u2_mid.values).max()
        print(f"  {a:9s} max |du2_mid| {1e6 * d:8.3f} um   max |u3_mid| {np.abs(sp.u3_mid.values).max():.1e} m   "
              f"peak u2_mid {1e3 * np.abs(pl.u2_mid.values).max():.4f} mm")
    print(f"spatial-slider-crank ({args.modes} modes, 0-{args.t_end:g} s)")
    runs = {a: run("spatial-slider-crank", {**base, "beam.axial_force": a}) for a in SETTINGS}
    for a, ds in runs.items():
        print(f"  {a:9s} peak |u2_mid| {1e6 * np.abs(ds.u2_mid.values).max():9.3f} um   "
              f"peak |u3_mid| {1e6 * np.abs(ds.u3_mid.values).max():9.3f} um")
    for v in ("u2_mid", "u3_mid"):
        d = np.abs(runs["inertial"][v].values - runs["none"][v].values).max()
        print(f"  the axial force moves {v} by up to {1e6 * d:.3f} um")
    print(f"cost: warm simulate, median of {args.repeats}")
    for scenario, extra in (("paper-dry", {"beam.model": "spatial"}), ("spatial-slider-crank", {})):
        for a in SETTINGS:
            sets = {**base, **extra, "beam.axial_force": a}
            run(scenario, sets)
            times = []
            for _ in range(args.repeats):
                t0 = time.perf_counter()
                ds = run(scenario, sets)
                times.append(time.perf_counter() - t0)
            print(f"  {scenario:22s} {a:9s} {1e3 * statistics.median(times):9.1f} ms   {ds.attrs['nfev']:7d} "
                  "right-hand sides")


if __name__ == "__main__":
    main()
