"""Checks of the ``paper-impact`` scenario behind docs/paper.md (Fig. 9): robustness, tension, cavitation.

    python tools/figures/fig9_checks.py [OUTDIR]       # default docs/figures; about 5 min on a busy core

Writes ``fig9-checks.md`` (atomically) and prints it:

1. the first impact of ``paper-impact`` under other discretisations of the film (Gauss-Legendre
   nodes), other integrators (Radau, Bulirsch-Stoer, exponential), tight tolerances and the numpy
   backend;
2. the window of clearances around the scenario's whose first impact is within 2 ms of 1.273 s
   (:func:`lubelink.paper.branches.find_windows`) for the film on 32, 16 and 64 nodes and at
   rtol 1e-10: how far the scenario's clearance is from its edges and from the jumps of ``t1(H)``;
3. the film pressure before the impact: when the oil first carries tension (absolute pressure
   below zero), the lowest gauge pressure and the pull of the film just before the impact;
4. the first impact with cavitation (half-Sommerfeld at zero absolute and at ambient pressure,
   Reynolds/Swift-Stieber);
5. the status of the restitution run.
"""

from __future__ import annotations

import io
import sys
import time
from pathlib import Path

import numpy as np

import lubelink
from lubelink._files import atomic_path
from lubelink.paper import PAPER_IMPACT_TIME, first_impact_time
from lubelink.paper.branches import find_windows

TOL = 2e-3


def t1(settings, t_stop=2.0):
    return first_impact_time(lubelink.resolve_config("paper-impact", settings), t_stop)


def main(out="docs/figures"):
    began = time.perf_counter()
    base = lubelink.resolve_config("paper-impact")
    H0, pad, mu = base.film.clearance, base.film.pad_length, base.film.viscosity
    text = io.StringIO()

    def say(line=""):
        print(line, flush=True)
        text.write(line + "\n")

    say(f"# Checks of paper-impact: H = {H0 * 1e3:.7f} mm, l = {pad * 1e3:g} mm, mu = {mu * 1e3:g} mPa s, "
        f"{base.beam.modes} mode(s)\n")
    # 1. other discretisations and integrators ----------------------------------------------------
    variants = [
        ("32 Gauss nodes, DOP853, rtol 1e-8 (the scenario)", {}),
        ("16 nodes", {"film.quadrature_nodes": 16}),
        ("64 nodes", {"film.quadrature_nodes": 64}),
        ("128 nodes", {"film.quadrature_nodes": 128}),
        ("rtol 1e-10, atol 1e-14", {"solver.rtol": 1e-10, "solver.atol": 1e-14}),
        ("64 nodes, rtol 1e-10, atol 1e-14", {"film.quadrature_nodes": 64, "solver.rtol": 1e-10,
                                              "solver.atol": 1e-14}),
        ("Bulirsch-Stoer", {"solver.method": "bulirsch-stoer"}),
        ("exponential Runge-Kutta", {"solver.method": "exponential"}),
        ("Radau (SciPy)", {"solver.method": "Radau"}),
        ("Radau, 64 nodes, rtol 1e-10", {"solver.method": "Radau", "film.quadrature_nodes": 64,
                                         "solver.rtol": 1e-10, "solver.atol": 1e-14}),
        ("numpy backend", {"solver.backend": "numpy"}),
        ("numpy backend, 64 nodes", {"solver.backend": "numpy", "film.quadrature_nodes": 64}),
    ]
    say("## First impact under other discretisations and integrators\n")
    say("| variant | first impact [s] | minus the scenario's [us] | minus 1.273 s [ms] |")
    say("|---|---|---|---|")
    ref = None
    for label, settings in variants:
        t = t1({**settings}, PAPER_IMPACT_TIME + 0.1)
        ref = t if ref is None else ref
        say(f"| {label} | {t:.7f} | {(t - ref) * 1e6:+.2f} | {(t - PAPER_IMPACT_TIME) * 1e3:+.3f} |")

    # 2. the window around H0 under several discretisations ----------------------------------------
    say("\n## The window of 1.273 s +- 2 ms around the scenario's clearance\n")
    say("| film, solver | window [mm] | width [nm] | H0 - lower edge [nm] | upper edge - H0 [nm] | "
        "branch (to the jumps) [mm] | H0 to the nearer jump [nm] (relative) |")
    say("|---|---|---|---|---|---|---|")
    grid = H0 + np.linspace(-20e-6, 20e-6, 41)
    for label, settings in variants[:3] + variants[4:5]:
        ws = find_windows(lambda H, s=settings: t1({**s, "film.clearance": float(H)}, PAPER_IMPACT_TIME + 0.1),
                          grid, PAPER_IMPACT_TIME, TOL, dx=2.5e-7, xtol=1e-11)
        w = [w for w in ws if w.lo <= H0 <= w.hi]
        if not w:
            say(f"| {label} | none holds H0 | | | | | |")
            continue
        w = w[0]
        near = min(H0 - w.branch[0], w.branch[1] - H0)
        say(f"| {label} | {w.lo * 1e3:.7f} - {w.hi * 1e3:.7f} ({w.lo_exit}/{w.hi_exit}) | {w.width * 1e9:.0f} | "
            f"{(H0 - w.lo) * 1e9:.0f} | {(w.hi - H0) * 1e9:.0f} | {w.branch[0] * 1e3:.7f} - {w.branch[1] * 1e3:.7f} | "
            f"{near * 1e9:.0f} ({near / H0:.1e}) |")

    scan = [w for w in find_windows(lambda H: t1({"film.clearance": float(H)}, PAPER_IMPACT_TIME + 0.1), grid,
                                    PAPER_IMPACT_TIME, TOL, dx=2.5e-7, xtol=1e-11) if w.lo <= H0 <= w.hi]
    if scan:
        H = np.linspace(scan[0].lo, scan[0].hi, 141)
        times = np.array([t1({"film.clearance": float(h)}, PAPER_IMPACT_TIME + 0.1) for h in H])
        say(f"\nDense scan of the scenario's window, {H.size} clearances {np.diff(H)[0] * 1e9:.0f} nm apart: first "
            f"impacts {times.min():.6f} to {times.max():.6f} s, all within 2 ms of 1.273 s: "
            f"{bool(np.all(np.abs(times - PAPER_IMPACT_TIME) <= TOL))}")

    # 3. tension in the oil ----------------------------------------------------------------------
    t_first = t1({}, PAPER_IMPACT_TIME + 0.1)
    ds = lubelink.simulate("paper-impact", {"contact.law": "none", "solver.t_end": t_first,
                                            "solver.output_step": 2e-5, "output.pad_points": 81,
                                            "output.x_points": 3})
    p_am = base.film.ambient_pressure
    p_min = ds.pressure.min("x_pad").values
    t = ds.time.values
    say("\n## Tension in the oil before the first impact (the paper's film, no cavitation)\n")
    below = np.flatnonzero(p_min < -p_am)
    say(f"* ambient pressure {p_am / 1e3:.3f} kPa; lowest gauge pressure before t = {t_first - 0.01:.4f} s: "
        f"{p_min[t < t_first - 0.01].min() / 1e3:.2f} kPa")
    if below.size:
        say(f"* absolute pressure first below zero (tension) at t = {t[below[0]]:.5f} s "
            f"({(t_first - t[below[0]]) * 1e3:.2f} ms before the impact), thinnest film then "
            f"{ds.film_min.values[below[0]] * 1e6:.1f} um")
    for dt in (5e-3, 1e-3, 2e-4, 1e-4):
        k = int(np.searchsorted(t, t_first - dt))
        say(f"* {dt * 1e3:g} ms before the impact: lowest gauge pressure {p_min[k] / 1e3:.1f} kPa, film force "
            f"{ds.film_force.values[k]:+.2f} N (positive: toward the collar), thinnest film "
            f"{ds.film_min.values[k] * 1e6:.1f} um")
    # 4. cavitation -----------------------------------------------------------------------------
    say("\n## With cavitation\n")
    say("| cavitation | first impact [s] | crank angle [deg] | thinnest film over 0-2 s [um] (at t [s]) |")
    say("|---|---|---|---|")
    for label, settings in [("none (the paper)", {}),
                            ("half-Sommerfeld at 0 Pa absolute", {"film.cavitation": "half-sommerfeld",
                                                                  "film.cavitation_pressure": 0.0}),
                            ("half-Sommerfeld at ambient", {"film.cavitation": "half-sommerfeld",
                                                            "film.cavitation_pressure": p_am}),
                            ("Reynolds (Swift-Stieber) at ambient", {"film.cavitation": "reynolds",
                                                                     "film.cavitation_pressure": p_am})]:
        tc = t1(settings)
        angle = np.degrees(np.mod(tc * base.mechanism.crank_speed, 2 * np.pi)) if np.isfinite(tc) else np.nan
        run = lubelink.simulate("paper-impact", {**settings, "contact.law": "none", "output.x_points": 3,
                                                 "output.pad_points": 5})
        k = int(np.argmin(run.film_min.values))
        thinnest = (f"breakdown ({base.contact.min_film * 1e6:g})" if run.attrs["status"] == "film_breakdown"
                    else f"{run.film_min.values[k] * 1e6:.1f} ({run.time.values[k]:.4f})")
        say(f"| {label} | {tc:.5f} | {angle:.0f} | {thinnest} |")
    # 5. the restitution run -------------------------------------------------------------------
    full = lubelink.simulate("paper-impact", {"output.x_points": 3, "output.pad_points": 5})
    times = full.impact_time.values
    say(f"\n## The restitution run\n\nstatus `{full.attrs['status']}` at t = {float(full.time[-1]):.6f} s after "
        f"{times.size} impacts ({times[0]:.6f} to {times[-1]:.6f} s): {full.attrs['message']}")
    say(f"\n({time.perf_counter() - began:.0f} s)")
    with atomic_path(Path(out) / "fig9-checks.md") as tmp:
        tmp.write_text(text.getvalue(), encoding="utf-8")


if __name__ == "__main__":
    main(*sys.argv[1:2])
