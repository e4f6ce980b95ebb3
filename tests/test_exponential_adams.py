"""The exponential Adams predictor-corrector (integrate/exponential_adams.py) against independent references.

* a free damped oscillator is integrated exactly, whatever the step (the load is zero);
* its fit is the interpolating polynomial (a polynomial of degree five is reproduced);
* order six with fixed steps (the fitted slope), the error follows the tolerance, and the number
  of steps does not follow the stiffest frequency;
* through the driver: the dense output between steps, against a tight DOP853 run;
* the paper's dry link against DOP853 at rtol 1e-12, and impacts (each segment starts again from
  the Runge-Kutta steps) at the times the other methods find.
"""

import importlib
import math

import numpy as np

from lubelink.config import resolve
from lubelink.integrate import exponential_adams as A
from lubelink.integrate import Options, Problem, integrate, method
from test_exponential import forced, free, free_exact, no_event

run = importlib.import_module("lubelink.simulate").run


def run_adams(p, t_end, rtol=1e-8, atol=1e-12, t_eval=None, **kw):
    omegas = p[3:]
    return integrate(method("exponential-adams"), Problem(forced, no_event, np.asarray(p, float), omega=omegas, zeta=p[0]),
                     0.0, np.zeros(2 * len(omegas)), t_end, np.zeros(0) if t_eval is None else t_eval,
                     Options(rtol=rtol, atol=atol, **kw))


def test_a_free_damped_oscillator_is_integrated_exactly_in_long_steps():
    w, zeta = 300.0, 0.02
    seg = integrate(method("exponential-adams"), Problem(free, no_event, np.array([w, zeta]), omega=[w], zeta=zeta), 0.0,
                    np.array([1e-3, 0.0]), 2.0, np.linspace(0.1, 2.0, 20), Options(rtol=1e-12, atol=1e-18))
    assert seg.nsteps < 40  # the error estimates vanish: from the starting step on, the step doubles (MAX_GROWTH)
    np.testing.assert_allclose(seg.y[:, 0], free_exact(seg.t, w, zeta, 1e-3, 0.0), rtol=0, atol=1e-15)


def test_the_shared_fit_reproduces_a_polynomial_of_its_degree_on_uneven_nodes():
    """Loads on a quintic at uneven nodes: the predictor's and the corrector's polynomials (the shared
    quartic plus each one's multiple of the node polynomial) are that quintic, and so is the dense
    output's load ``R_Q``; ``R_MPI`` is ``h sum_k k! pi_k phi_(k+1)`` of the tables."""
    rng = np.random.default_rng(3)
    D = A.DEGREE
    N = 3
    coefficients = rng.normal(size=(D + 1, 2 * N))
    nodes = np.array([0.0, -0.7, -1.9, -2.4, -3.1, -4.6, -5.0])[:D + 1]
    W = np.zeros((A.ROWS_END, 2 * N))
    fst = np.zeros(A.FLOATS)
    W[A.E.R_LIN] = np.r_[[40.0, 300.0, 2000.0], [0.0, 0.02, 0.3]]
    h = 2e-3
    A.E._tables(W, h, 1.0, A.R_ATABLE, A.ORDER + 1)
    value = lambda s: sum(coefficients[k] * s**k for k in range(D + 1))
    W[A.E.R_G] = value(0.0)
    for i in range(D):
        W[A.R_HIST + i] = value(nodes[i + 1])
    fst[A.F_NODES:A.F_NODES + D + 1] = nodes
    A._shared(W, fst, h)
    np.testing.assert_allclose(W[A.R_AP], coefficients[D], rtol=1e-9)
    W[A.E.R_GNEW] = value(1.0)
    A._corrector_coefficient(W, fst)
    np.testing.assert_allclose(W[A.R_AC], coefficients[D], rtol=1e-9)
    A._corrector_polynomial(W, fst)
    np.testing.assert_allclose(W[A.E.R_Q:A.E.R_Q + D + 1], coefficients, rtol=1e-10, atol=1e-10)
    pi = np.poly1d(np.poly(nodes[:D]))  # prod (s - x_k), highest power first
    weights = [h * math.factorial(k) * pi.coeffs[::-1][k] for k in range(D + 1)]
    T = A.R_ATABLE
    np.testing.assert_allclose(W[A.R_MPI], sum(w * W[T + k + 1] for k, w in enumerate(weights)), rtol=1e-12)


def test_order_six_with_fixed_steps():
    """Two oscillators (w = 50 and 3000), cos forcing and a weak quadratic load; the step is held at
    ``max_step`` (the tolerances accept anything). Fitted slope 6.8 (measured); the five starting
    steps of the fourth-order Runge-Kutta method, a fixed number, add an ``O(h^5)`` part."""
    p = np.array([0.01, 2.0, 3.0, 50.0, 3000.0])
    ref = run_adams(p, 1.0, rtol=1e-13, atol=1e-18).y_final
    hs = 1.0 / np.array([30, 45, 60, 90])
    errors = [np.max(np.abs(run_adams(p, 1.0, rtol=1.0, atol=1.0, max_step=h).y_final - ref)) for h in hs]
    slope = np.polyfit(np.log(hs), np.log(errors), 1)[0]
    assert 5.5 < slope < 7.5, (errors, slope)


def test_error_follows_the_tolerance_and_the_dense_output_is_accurate():
    """At 20 samples between the steps (dense output), against DOP853 at rtol 1e-13."""
    p = np.array([0.01, 2.0, 3.0, 50.0, 400.0])
    t_eval = np.linspace(0.1, 2.0, 20) + 1.234e-3
    ref = integrate(method("DOP853"), Problem(forced, no_event, p), 0.0, np.zeros(4), 2.0 + 1.234e-3, t_eval,
                    Options(rtol=1e-13, atol=1e-18)).y
    ratios = []
    for rtol in (1e-6, 1e-8, 1e-10):
        seg = run_adams(p, t_eval[-1], rtol=rtol, atol=rtol * 1e-4, t_eval=t_eval)
        ratios.append(np.max(np.abs(seg.y - ref) / np.abs(ref).max(axis=0)) / rtol)
    assert max(ratios) < 100 and max(ratios) / min(ratios) < 100, ratios


def test_the_steps_do_not_follow_the_stiffest_frequency():
    steps = [run_adams(np.array([0.01, 0.0, 3.0, 10.0, w_max]), 2.0, rtol=1e-8, atol=1e-10).nsteps
             for w_max in (1e2, 1e4)]
    assert steps[1] <= 1.2 * steps[0], steps


def test_the_dry_link_against_a_tight_reference():
    """``paper-dry`` with 5 modes at the default tolerances: within 0.1 um of DOP853 at rtol 1e-12
    (measured 0.01 um), in two evaluations a step after the five starting steps."""
    over = {"beam.modes": 5, "solver.t_end": 1.0}
    adams = run(resolve("paper-dry", {**over, "solver.method": "exponential-adams"}))
    ref = run(resolve("paper-dry", {**over, "solver.method": "DOP853", "solver.rtol": 1e-12, "solver.atol": 1e-14}))
    mid = np.sin(np.arange(1, 6) * np.pi / 2)
    assert adams.complete and adams.t.size == ref.t.size
    assert np.max(np.abs((adams.y - ref.y)[:, :5] @ mid)) < 1e-7
    assert adams.nfev <= 2 * adams.nsteps + A.DEGREE * 7 + 1 + 2 + 2 * adams.nsteps * 0.2  # + starts, rejections


def test_impacts_at_the_times_the_other_methods_find():
    """Film-less impacts (tests/test_simulate.py's ``IMPACT``): every segment after an impact starts
    again with Runge-Kutta steps; the impacts agree with DOP853 at rtol 1e-11 within 3e-7 s (measured
    4e-9 and 1.3e-7 s; the order-four method of version 0.1 1.7e-8 and 2.7e-8 s, DOP853 at the default
    tolerances 2.5e-9 and 1.6e-8 s)."""
    impact = {"film.model": "none", "film.clearance": 5e-3, "contact.law": "restitution", "beam.modes": 3,
              "solver.t_end": 0.5}
    adams = run(resolve("paper", {**impact, "solver.method": "exponential-adams"}))
    tight = run(resolve("paper", {**impact, "solver.method": "DOP853", "solver.rtol": 1e-11, "solver.atol": 1e-14}))
    assert adams.complete and len(adams.impacts) == len(tight.impacts) >= 2
    np.testing.assert_allclose([i[0] for i in adams.impacts], [i[0] for i in tight.impacts], rtol=0, atol=3e-7)
