"""Mode convergence of the first contact of a dry guide: the compliant law at a point and over the pad.

``python tools/figures/contact_convergence.py`` prints the table of docs/model.md section 5.4: the
paper's slider-crank with a dry joint of 0.1 mm clearance (``film.model = "none"``), contact at
``min_film = 1 um``, the link released from rest, so the first contact comes from the start of the
crank (5.6 ms). For N = 1, 3, 7, 15, 31 modes and both extents of the compliant law it gives, up to
12 ms, the first contact's start, the number of contacts, the peak force, the impulse of all the
contacts and the deepest penetration below ``min_film``.
"""

from __future__ import annotations

import argparse

import numpy as np

import lubelink

SETTINGS = {"film.model": "none", "film.clearance": 1e-4, "contact.law": "compliant", "contact.min_film": 1e-6,
            "solver.t_end": 0.012, "solver.output_step": 1e-6, "solver.rtol": 1e-8, "solver.atol": 1e-12}


def contact_window(modes, extent, **more):
    """``(first start [s], contacts, peak force [N], impulse [N s], deepest penetration [m])`` up to ``t_end``."""
    ds = lubelink.simulate("paper", {**SETTINGS, "beam.modes": modes, "contact.extent": extent, **more})
    t, force = ds.time.values, ds.contact_force.values
    impulse = float(np.trapezoid(force, t))
    depth = float(SETTINGS["contact.min_film"] - ds.film_min.values.min())
    return float(ds.impact_time[0]), ds.impact.size, float(force.max()), impulse, depth


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--modes", type=int, nargs="*", default=[1, 3, 7, 15, 31])
    args = parser.parse_args(argv)
    print("| extent | N | first contact [ms] | contacts | peak force [N] | impulse [mN s] | deepest below min_film [um] |")
    print("|---|---|---|---|---|---|---|")
    for extent in ("point", "pad"):
        for n in args.modes:
            start, count, peak, impulse, depth = contact_window(n, extent)
            print(f"| {extent} | {n} | {1e3 * start:.5f} | {count} | {peak:.4g} | {1e3 * impulse:.4g} | "
                  f"{1e6 * depth:.4g} |", flush=True)


if __name__ == "__main__":
    main()
