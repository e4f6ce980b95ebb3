"""Exponential Adams predictor-corrector for damped oscillators with a nonlinear load.

The problems of :mod:`.exponential`, ``y' = A y + G(t, y)`` with ``A`` block diagonal, by the
exponential Adams methods of Hochbruck & Ostermann (*Exponential integrators*, Acta Numerica 19
(2010) 209-286, Section 2.5): the load is replaced by the quintic ``G(t_n + sigma h) ~ sum_k Q_k
sigma^k`` through its values at six points, and the variation-of-constants formula integrated
exactly with it::

    y_(n+1) = phi_0(hA) y_n + h sum_k k! phi_(k+1)(hA) Q_k

(:func:`_solution`). The step is a PECE pair of order six on variable steps:

* predict with the quintic through the loads at ``t_n`` and the five steps before (extrapolated);
* evaluate the load there, correct with the quintic through ``t_(n+1)``, ``t_n`` and four steps before;
* the difference of the two is the error estimate (Milne's device: for constant steps the
  corrector's error is ``863/19950`` of it, :data:`MILNE`), evaluate the load at the corrected
  state: two evaluations a step against the Runge-Kutta method's seven.

Order six, not four: on the dry link (``paper-dry``, 1-15 modes, crank speed to 80 rad/s) it takes
half the steps of the order-four pair of version 0.1 at the same tolerances, with half its error;
its step costs more (the tables ``phi_0 .. phi_6``, fits of six loads), so a run takes 0.73-0.85x
the time (benchmarks/README.md). The corrector's quintic is the load over the step, so the dense
output is that of the Runge-Kutta method (:mod:`.exponential_dense`) with a quintic load. A
segment starts with five steps of the Runge-Kutta method (:func:`.exponential.rk_step`), which
leave the loads the first Adams step needs; so does every segment after an event. The multistep
method pays for its cheap steps with a smaller stability region: where the load depends strongly
on the state (a lubricant film, the spatial link's coupling) its steps are held short, and its
error at loose tolerances is less reliable than the Runge-Kutta method's (docs/model.md section 7.1).
"""

import numpy as np

from lubelink._jit import jitable, kernel
from ._layout import F_DIR, F_H, F_HSTEP, F_MAXSTEP, F_T, F_TOLD, FAIL_RHS, R_Y, S_FAIL, S_NFEV, S_NREJ
from . import exponential as E
from .control import MIN_FACTOR, min_step, scaled_rms, step_end, step_factor

__all__ = ["init", "step", "rows", "setup", "FLOATS"]

#: Order of the pair, and the number of loads its polynomials go through.
ORDER = 6
DEGREE = ORDER - 1
#: Corrector error over (corrector - predictor) for constant steps: ``C_c / (C_c - C_p)`` with the
#: error constants of the Adams-Moulton corrector and the Adams-Bashforth predictor of order six,
#: ``-863/60480`` and ``19087/60480`` (order four: ``-19/720``, ``251/720``, giving ``19/270``).
MILNE = 863.0 / 19950.0
#: Largest growth of the step from one step to the next: the variable-step coefficients stay
#: near the constant-step ones, whose stability the pair has.
MAX_GROWTH = 2.0

R_HIST = E.ROWS_END  # the loads at t_(n-1) .. t_(n-DEGREE): DEGREE rows
R_ATABLE = R_HIST + DEGREE  # phi_0 .. phi_ORDER of h A for the Adams step: ORDER + 1 rows
R_YPRED = R_ATABLE + ORDER + 1
R_GPREV = R_YPRED + 1  # the load at the start of a Runge-Kutta starting step
ROWS_END = R_GPREV + 1
F_THIST = E.FLOATS  # t_(n-1) .. t_(n-DEGREE)
F_NHIST = F_THIST + DEGREE  # loads in the history (DEGREE: the Adams steps run)
F_AHOLD = F_NHIST + 1  # the step R_ATABLE was made for
F_NODES = F_AHOLD + 1  # the nodes of the fit in sigma: ORDER slots
FLOATS = F_NODES + ORDER

setup = E.setup


def rows(n):
    """Rows of ``W`` this method uses."""
    return ROWS_END


@kernel
def init(rhs, p, W, fst, ist):
    """The Runge-Kutta method's start (``G`` at ``t0``, the starting step), an empty history."""
    E.rk_init(rhs, p, W, fst, ist)
    fst[F_NHIST] = 0.0
    fst[F_AHOLD] = np.nan


@jitable
def _fit(W, fst, r0, r1, h0):
    """``R_Q``: the polynomial of degree :data:`DEGREE` in ``sigma`` through the loads at the nodes
    ``fst[F_NODES ..]``: rows ``r0``, ``r1`` at the first two, the history rows from ``R_HIST + h0`` on
    at the others.

    Newton's divided differences, then the monomial coefficients by expanding the Newton form from
    its innermost factor, ``P_k(s) = a_k + (s - x_k) P_(k+1)(s)``, in place. Each pass runs over
    all components at once with its node difference in a register: the components are independent,
    so the passes pipeline (0.5 us a fit with 10 components column by column, where every operation
    waited for the one before).
    """
    n = W.shape[1]
    for m in range(n):
        W[E.R_Q, m] = W[r0, m]
        W[E.R_Q + 1, m] = W[r1, m]
    for i in range(2, DEGREE + 1):
        for m in range(n):
            W[E.R_Q + i, m] = W[R_HIST + h0 + i - 2, m]
    for order in range(1, DEGREE + 1):
        for i in range(DEGREE, order - 1, -1):
            c = 1.0 / (fst[F_NODES + i] - fst[F_NODES + i - order])
            for m in range(n):
                W[E.R_Q + i, m] = (W[E.R_Q + i, m] - W[E.R_Q + i - 1, m]) * c
    for k in range(DEGREE - 1, -1, -1):
        x = fst[F_NODES + k]
        for i in range(k, DEGREE):
            for m in range(n):
                W[E.R_Q + i, m] -= x * W[E.R_Q + i + 1, m]


@jitable
def _solution(W, h, r_y, r_out):
    """``phi_0(h A) y + h sum_k k! phi_(k+1)(h A) Q_k`` into row ``r_out``: the variation-of-constants
    formula with the load replaced by the polynomial ``R_Q``, integrated exactly."""
    T = R_ATABLE
    Q = E.R_Q
    E._phi_sum(W, r_out, (T, T + 1, T + 2, T + 3, T + 4, T + 5, T + 6), (r_y, Q, Q + 1, Q + 2, Q + 3, Q + 4, Q + 5),
               (1.0, h, h, 2.0 * h, 6.0 * h, 24.0 * h, 120.0 * h))


@jitable
def _push(W, fst, row, t):
    """The load in ``row`` at ``t`` becomes the newest of the history."""
    for m in range(W.shape[1]):
        for i in range(DEGREE - 1, 0, -1):
            W[R_HIST + i, m] = W[R_HIST + i - 1, m]
        W[R_HIST, m] = W[row, m]
    for i in range(DEGREE - 1, 0, -1):
        fst[F_THIST + i] = fst[F_THIST + i - 1]
    fst[F_THIST] = t
    fst[F_NHIST] = min(fst[F_NHIST] + 1.0, float(DEGREE))


@kernel
def step(rhs, p, W, fst, ist):
    """One accepted step: the Runge-Kutta method's while the history fills, then the PECE pair."""
    n = W.shape[1]
    if fst[F_NHIST] < DEGREE:
        for m in range(n):
            W[R_GPREV, m] = W[E.R_G, m]
        if not E.rk_step(rhs, p, W, fst, ist):
            return False
        _push(W, fst, R_GPREV, fst[F_TOLD])
        return True
    t = fst[F_T]
    smallest = min_step(t, fst[F_DIR])
    h_abs = min(fst[F_H], fst[F_MAXSTEP], MAX_GROWTH * abs(fst[F_HSTEP]))
    rejected = False
    while True:
        if h_abs < smallest:
            return False
        t_new = step_end(fst, t, h_abs)
        h = t_new - t
        if h != fst[F_AHOLD]:
            E._tables(W, h, 1.0, R_ATABLE, ORDER + 1)
            fst[F_AHOLD] = h
        fst[F_NODES] = 0.0  # predictor: the loads at t_n and the DEGREE steps before
        for i in range(DEGREE):
            fst[F_NODES + 1 + i] = (fst[F_THIST + i] - t) / h
        _fit(W, fst, E.R_G, R_HIST, 1)
        _solution(W, h, R_Y, R_YPRED)
        rhs(t_new, W[R_YPRED], W[E.R_FU], p)
        ist[S_NFEV] += 1
        E._load(W, R_YPRED, E.R_FU, E.R_GNEW)
        fst[F_NODES] = 1.0  # corrector: the predicted load at t_(n+1), then t_n and DEGREE - 1 steps before
        for i in range(DEGREE):
            fst[F_NODES + 1 + i] = 0.0 if i == 0 else (fst[F_THIST + i - 1] - t) / h
        _fit(W, fst, E.R_GNEW, E.R_G, 0)
        _solution(W, h, R_Y, E.R_YNEW)
        for m in range(n):
            W[E.R_ERR, m] = MILNE * (W[E.R_YNEW, m] - W[R_YPRED, m])
        err = scaled_rms(W[E.R_ERR], W[R_Y], W[E.R_YNEW], W)
        if not np.isfinite(err):
            ist[S_FAIL] = FAIL_RHS
            err = 1.0 / MIN_FACTOR ** (ORDER + 1)
        factor = step_factor(err, ORDER, rejected)
        if E.KEEP_LOW <= factor <= E.KEEP_HIGH:
            factor = 1.0  # the tables serve the next step too
        h_abs = abs(h) * factor
        if err < 1.0:
            ist[S_FAIL] = 0
            break
        rejected = True
        ist[S_NREJ] += 1
    rhs(t_new, W[E.R_YNEW], W[E.R_FU], p)  # the load at the corrected state: the next step's G_n
    ist[S_NFEV] += 1
    E._load(W, E.R_YNEW, E.R_FU, E.R_GNEW)
    _push(W, fst, E.R_G, t)
    fst[E.F_DEGREE] = float(DEGREE)  # the dense output's load: the corrector's polynomial
    E.accept(W, fst, ist, t, t_new, h_abs)
    return True
