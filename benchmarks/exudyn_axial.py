"""paper-dry with and without the axial force (beam.axial_force) against a converged Exudyn model, and its cost.

The finite-element reference is ``exudyn_rod.py``'s model (Exudyn 1.13.6, ANCF cable elements: geometrically
exact, extensible, with axial inertia; the crank pin driven, a massless slider on the X axis), run in its side
interpreter (set it up as that script says) at ``--elements`` and ``--step`` (default 32 and 2.5e-5 s: 64
elements at the same step differ from it by 0.08 µm, 16 at 5e-5 s by 0.5 µm). lubelink runs
``simulate("paper-dry", {"beam.modes": N, "beam.axial_force": ...})`` for each ``--modes``. Printed: the
largest mid-span difference over 0-2 s and over each half second (a difference that grows steadily is a
frequency offset of mode 1), and what a mode-1 frequency offset ``d(omega_1^2)`` added to lubelink's
``"inertial"`` model leaves (the residual's nature; the offset is found by a golden-section search on the
standalone modal model of :func:`offset_model`, which reproduces lubelink's run to 1 nm).

Then ``--cost``: warm ``simulate`` wall times of ``paper-dry`` and ``paper`` (5 modes) with each setting,
median of ``--repeats`` (run with ``LUBELINK_FIRST_RUN=compile`` so the first call compiles).

    python benchmarks/exudyn_axial.py                       # the comparison and the cost (minutes)
    python benchmarks/exudyn_axial.py --elements 16 --step 5e-5 --modes 5,10
    python benchmarks/exudyn_axial.py --cost-only --repeats 7
"""

from __future__ import annotations

import argparse
import os
import statistics
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
import exudyn_rod  # noqa: E402  (the finite-element model and its side interpreter)

SETTINGS = ("none", "inertial")


def lubelink_run(modes, setting, scenario="paper-dry"):
    import lubelink

    ds = lubelink.simulate(scenario, {"beam.modes": modes, "beam.axial_force": setting})
    if ds.attrs["status"] != "complete":
        sys.exit(f"lubelink run incomplete: {ds.attrs['status']}")
    return ds.time.values, ds.u2_mid.values


def offset_model(t_eval, modes, d_omega2):
    """u2_mid [m] of paper-dry with the axial force and mode 1's ``omega_1^2`` raised by ``d_omega2`` [1/s^2]:
    the modal equations written out (lubelink's kinematics and :mod:`lubelink.link.axial`, with the chord's
    rotation), DOP853 at 1e-10."""
    from scipy.integrate import solve_ivp

    from lubelink.config import resolve
    from lubelink.link import axial
    from lubelink.link.kinematics import pin_axial_acceleration, slider_crank

    c = resolve("paper-dry", {"beam.modes": modes})
    m, b = c.mechanism, c.beam
    L, rA = m.rod_length, b.density * b.area
    n = np.arange(1, modes + 1)
    beta = n * np.pi / L
    w2 = beta**4 * b.youngs_modulus * b.second_moment / rA
    w2[0] += d_omega2
    P = axial.slope_moments(modes, L)
    lever, slopes = axial.chord_levers(modes, L)
    sign = (-1.0) ** (n + 1)

    def f(t, y):
        k = slider_crank(t, m.crank_length, L, m.crank_speed, m.guide_distance)
        angle = -k["theta"]
        A1 = pin_axial_acceleration(t, angle, m.crank_length, m.crank_speed)
        terms = axial.rigid_axial_force(A1, k["A_O2"], k["omega"], k["alpha"], angle, 0.0, k["x_star"], (0.0, 0.0),
                                        rA, L)
        q, v = y[:modes], y[modes:]
        g = -2.0 / (L * beta) * (k["A_O2"] * (1 + sign) + k["alpha"] * L * sign)
        acc = -(w2 - k["omega"] ** 2) * q + g - axial.geometric_stiffness(P, terms) @ q / (rA * L / 2)
        axial.chord_rotation(lever, slopes, rA, L, rA * L / 2, angle, k["omega"], k["alpha"], q, v, acc)
        return np.r_[v, acc]

    s = solve_ivp(f, (0.0, t_eval[-1]), np.zeros(2 * modes), method="DOP853", rtol=1e-10, atol=1e-13, t_eval=t_eval)
    return s.y[:modes].T @ np.sin(beta * L / 2)


def windows(t, d, width=0.5):
    return ", ".join(f"{1e6 * np.abs(d[(t >= a) & (t < a + width)]).max():.1f}"
                     for a in np.arange(0.0, t[-1] - 1e-9, width))


def compare(args):
    t0 = time.perf_counter()
    ref = exudyn_rod.run_exudyn(args.exudyn_python, args.elements, args.step, 1)
    print(f"Exudyn {ref['version']}: {args.elements} ANCFCable2D elements, h = {args.step:g} s "
          f"(solve {ref['solve'][0]:.1f} s, wall {time.perf_counter() - t0:.0f} s)")
    for modes in args.modes:
        for setting in SETTINGS:
            t, u = lubelink_run(modes, setting)
            d = u - np.interp(t, ref["t"], ref["u2_mid"])
            peak = np.abs(np.interp(t, ref["t"], ref["u2_mid"])).max()
            print(f"  {modes:2d} modes, axial_force = {setting!r:10}: max |u2_mid - FE| {1e6 * np.abs(d).max():5.1f} µm "
                  f"({100 * np.abs(d).max() / peak:.2f} % of the peak {1e3 * peak:.4f} mm); per 0.5 s: {windows(t, d)}")
    from scipy.optimize import minimize_scalar

    modes = args.modes[0]
    t, u = lubelink_run(modes, "inertial")
    fe = np.interp(t, ref["t"], ref["u2_mid"])
    same = np.abs(offset_model(t, modes, 0.0) - u).max()

    def residual(dw2):
        return np.abs(offset_model(t, modes, dw2) - fe).max()

    best = minimize_scalar(residual, bounds=(-10.0, 20.0), method="bounded", options={"xatol": 0.2})
    w1 = (np.pi / 1.0) ** 2 * np.sqrt(207e9 * 1e-8 / 12 / (7650.0 * 1e-4))
    print(f"  the modal model written out reproduces lubelink's 'inertial' run to {1e9 * same:.1f} nm; with mode 1's "
          f"omega_1^2 raised by {best.x:.2f} 1/s^2 ({0.5 * best.x / w1**2:.2e} of omega_1) it is "
          f"{1e6 * best.fun:.1f} µm from the FE model")


def cost(args):
    import lubelink

    for scenario in ("paper-dry", "paper"):
        for setting in SETTINGS:
            overrides = {"beam.modes": 5, "beam.axial_force": setting}
            t0 = time.perf_counter()
            lubelink.simulate(scenario, overrides)
            first = time.perf_counter() - t0
            walls = []
            for _ in range(args.repeats):
                t0 = time.perf_counter()
                lubelink.simulate(scenario, overrides)
                walls.append(time.perf_counter() - t0)
            print(f"  simulate({scenario!r}, 5 modes, axial_force = {setting!r}): median {1e3 * statistics.median(walls):.1f} ms "
                  f"of {len(walls)} ({1e3 * min(walls):.1f}-{1e3 * max(walls):.1f}); first call {first:.1f} s")


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--exudyn-python", default="/tmp/exuenv/bin/python")
    parser.add_argument("--elements", type=int, default=32)
    parser.add_argument("--step", type=float, default=2.5e-5)
    parser.add_argument("--modes", type=lambda s: [int(v) for v in s.split(",")], default=[5, 10])
    parser.add_argument("--repeats", type=int, default=5)
    parser.add_argument("--cost-only", action="store_true")
    args = parser.parse_args()
    print(f"{os.cpu_count()} CPUs, load average {os.getloadavg()[0]:.1f} at start")
    if not args.cost_only:
        compare(args)
    print("cost (warm):")
    cost(args)


if __name__ == "__main__":
    main()
