"""Study of a candidate method, not part of lubelink: exponential Adams methods against the RK method.

The exponential Runge-Kutta method (``solver.method = "exponential"``) pays seven evaluations of
the right-hand side a step. An exponential Adams method (Hochbruck & Ostermann, *Exponential
integrators*, Acta Numerica 19 (2010), Section 2.5) pays one (explicit, ``EAB``) or two
(predictor-corrector, ``EAB PECE``) a step: the load ``G = f - A y`` is interpolated by a
polynomial through its values at the last ``k`` steps, ``G(t_n + s h) = sum_m c_m s^m``, and the
variation-of-constants formula integrated exactly with it,
``y_(n+1) = phi_0(hA) y_n + h sum_m m! phi_(m+1)(hA) c_m`` (the formula of the RK method's dense
output). This script measures, with fixed steps, the largest error of the midpoint deflection
``u2_mid`` over 0-1 s (samples every 1 ms) against DOP853 at ``rtol 1e-12``, and the number of
evaluations, beside the RK method at several tolerances; the Adams methods start from the
reference's first ``k - 1`` steps. The phi-functions come from the exponential of an augmented
matrix (SciPy's ``expm``), independent of :mod:`lubelink.integrate.phi`.

It answers one question before the method is built into the driver (step control, restarts at
impacts, dense output and events): how many evaluations it saves at equal accuracy. Measured
(2026-11-26): dry, 5 modes, about 4x fewer (EAB5 at h = 2 ms: 501 evaluations, 0.008 um;
the RK method 2060 evaluations for 0.005 um); with the film, 7 modes, about 1.4x (EAB5 at h = 0.5 ms:
2001 evaluations, 0.011 um; the RK method 2907 for 0.014 um): the film's stiff dependence on the
state holds the multistep methods' steps.

Usage::

    python benchmarks/exponential_adams_study.py                      # paper-dry, 5 modes
    python benchmarks/exponential_adams_study.py --scenario paper --modes 7
"""

from __future__ import annotations

import argparse
import importlib
import math

import numpy as np
from scipy.linalg import expm

from lubelink.config import resolve

SAMPLE, T_END = 1e-3, 1.0  # [s]


def problem(scenario, modes):
    """``(G, A, u2_mid weights, reference run, base overrides)`` of a scenario's right-hand side."""
    run = importlib.import_module("lubelink.simulate").run
    base = {"beam.modes": modes, "solver.t_end": T_END, "solver.output_step": SAMPLE}
    ref = run(resolve(scenario, {**base, "solver.rtol": 1e-12, "solver.atol": 1e-14, "solver.method": "DOP853"}))
    model = ref.model
    rhs, _ = model.functions()
    p = model.with_phase(None)
    omega = np.asarray(model.state_frequencies, float)
    zeta = float(model.config.beam.damping_ratio)
    n = 2 * modes
    A = np.zeros((n, n))
    for i in range(modes):
        A[i, modes + i], A[modes + i, i], A[modes + i, modes + i] = 1.0, -omega[i] ** 2, -2 * zeta * omega[i]

    def G(t, y):
        f = np.empty(n)
        rhs(t, y, f, p)
        return f - A @ y

    weights = np.concatenate([np.sin(np.arange(1, modes + 1) * np.pi / 2), np.zeros(modes)])
    return G, A, weights, ref, base


def phi_tables(hA, K):
    """``phi_0 .. phi_K`` of ``hA`` from the exponential of the augmented matrix."""
    n = hA.shape[0]
    M = np.zeros((n * (K + 1), n * (K + 1)))
    M[:n, :n] = hA
    for k in range(K):
        M[n * k:n * (k + 1), n * (k + 1):n * (k + 2)] = np.eye(n)
    E = expm(M)
    return [E[:n, :n]] + [E[:n, n * k:n * (k + 1)] for k in range(1, K + 1)]


def adams(G, A, start, h, k, pece):
    """Fixed steps of ``h`` over ``[0, T_END]``: ``(times, states, evaluations)``."""
    steps = int(round(T_END / h))
    P = phi_tables(h * A, k)
    W = [h * math.factorial(m) * P[m + 1] for m in range(k)]
    # monomial coefficients of the interpolant from its values at s = 0, -1, .. (predictor), 1, 0, .. (corrector)
    Vp = np.linalg.inv(np.array([[float(-j) ** m for m in range(k)] for j in range(k)]))
    Vc = np.linalg.inv(np.array([[float(1 - j) ** m for m in range(k)] for j in range(k)]))
    ys = list(start)
    loads = [G(j * h, y) for j, y in enumerate(start)]
    evaluations = len(start)
    y = ys[-1]
    for j in range(len(start) - 1, steps):
        t = j * h
        c = Vp @ np.array(loads[::-1][:k])
        y_new = P[0] @ y + sum(W[m] @ c[m] for m in range(k))
        g_new = G(t + h, y_new)
        evaluations += 1
        if pece:
            c = Vc @ np.array([g_new] + loads[::-1][:k - 1])
            y_new = P[0] @ y + sum(W[m] @ c[m] for m in range(k))
            g_new = G(t + h, y_new)
            evaluations += 1
        y = y_new
        ys.append(y)
        loads = (loads + [g_new])[-k:]
    return np.arange(steps + 1) * h, np.array(ys), evaluations


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--scenario", default="paper-dry")
    parser.add_argument("--modes", type=int, default=5)
    args = parser.parse_args()
    run = importlib.import_module("lubelink.simulate").run
    G, A, weights, ref, base = problem(args.scenario, args.modes)
    ref_mid = ref.y @ weights
    print(f"{args.scenario}, {args.modes} modes, 0-{T_END:g} s: largest error of u2_mid against DOP853 at rtol 1e-12")
    print("exponential RK (lubelink), atol = rtol / 100:")
    for tol in (1e-4, 1e-5, 1e-6, 1e-7):
        r = run(resolve(args.scenario, {**base, "solver.rtol": tol, "solver.atol": tol / 100,
                                        "solver.method": "exponential"}))
        print(f"  rtol {tol:g}: {r.nfev:5d} evaluations, {r.nsteps:4d} steps, "
              f"error {1e6 * np.max(np.abs(r.y @ weights - ref_mid)):.4f} um")
    print("exponential Adams, fixed steps:")
    for k in (4, 5, 6):
        start_run = None
        for pece in (False, True):
            for h in (4e-3, 2e-3, 1e-3, 5e-4):
                start_run = run(resolve(args.scenario, {**base, "solver.rtol": 1e-12, "solver.atol": 1e-14,
                                                        "solver.method": "DOP853", "solver.output_step": h,
                                                        "solver.t_end": (k - 1) * h * (1 + 1e-9)}))
                t, y, evaluations = adams(G, A, start_run.y[:k], h, k, pece)
                on_samples = np.abs(t / SAMPLE - np.rint(t / SAMPLE)) < 1e-6
                error = np.max(np.abs(y[on_samples] @ weights - ref_mid[np.rint(t[on_samples] / SAMPLE).astype(int)]))
                print(f"  EAB{k}{' PECE' if pece else '     '} h {1e3 * h:3g} ms: {evaluations:5d} evaluations, "
                      f"error {1e6 * error:.4f} um")


if __name__ == "__main__":
    main()
