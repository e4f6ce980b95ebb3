"""Exponential Adams predictor-corrector for damped oscillators with a nonlinear load.

The problems of :mod:`.exponential`, ``y' = A y + G(t, y)`` with ``A`` block diagonal, by the
exponential Adams methods of Hochbruck & Ostermann (*Exponential integrators*, Acta Numerica 19
(2010) 209-286, Section 2.5): the load is replaced by the cubic ``G(t_n + sigma h) ~ sum_k Q_k
sigma^k`` through its values at four points, and the variation-of-constants formula integrated
exactly with it::

    y_(n+1) = phi_0(hA) y_n + h sum_k k! phi_(k+1)(hA) Q_k

(:func:`.exponential._cubic_solution`). The step is a PECE pair of order four on variable steps:

* predict with the cubic through the loads at ``t_n, t_(n-1), t_(n-2), t_(n-3)`` (extrapolated);
* evaluate the load there, correct with the cubic through ``t_(n+1), t_n, t_(n-1), t_(n-2)``;
* the difference of the two is the error estimate (Milne's device: for constant steps the
  corrector's error is ``19/270`` of it, :data:`MILNE`), evaluate the load at the corrected state:
  two evaluations a step against the Runge-Kutta method's seven.

The corrector's cubic is the load over the step, so the dense output is that of the Runge-Kutta
method (:mod:`.exponential_dense`), unchanged. A segment starts with three steps of the
Runge-Kutta method (:func:`.exponential.rk_step`), which leave the loads the first Adams step
needs; so does every segment after an event. The multistep method pays for its cheap steps with
a smaller stability region: where the load depends strongly on the state (a lubricant film, the
spatial link's coupling) its steps are held short, and its error at loose tolerances is less
reliable than the Runge-Kutta method's (docs/model.md section 7.1).
"""

import numpy as np

from lubelink._jit import jitable, kernel
from ._layout import F_DIR, F_H, F_HSTEP, F_MAXSTEP, F_T, F_TOLD, FAIL_RHS, R_Y, S_FAIL, S_NFEV, S_NREJ
from . import exponential as E
from .control import MIN_FACTOR, min_step, scaled_rms, step_end, step_factor

__all__ = ["init", "step", "rows", "setup", "FLOATS"]

ORDER = 4
#: Corrector error over (corrector - predictor) for constant steps: ``C_c / (C_c - C_p)`` with the
#: error constants ``-19/720`` (corrector) and ``251/720`` (predictor) of the order-four pair.
MILNE = 19.0 / 270.0
#: Largest growth of the step from one step to the next: the variable-step coefficients stay
#: near the constant-step ones, whose stability the pair has.
MAX_GROWTH = 2.0

R_HIST = E.ROWS_END  # the loads at t_(n-1), t_(n-2), t_(n-3): 3 rows
R_ATABLE = R_HIST + 3  # phi_0 .. phi_4 of h A for the Adams step: 5 rows
R_YPRED = R_ATABLE + 5
R_GPREV = R_YPRED + 1  # the load at the start of a Runge-Kutta starting step
ROWS_END = R_GPREV + 1
F_THIST = E.FLOATS  # t_(n-1), t_(n-2), t_(n-3)
F_NHIST = F_THIST + 3  # loads in the history (3: the Adams steps run)
F_AHOLD = F_THIST + 4  # the step R_ATABLE was made for
FLOATS = F_THIST + 5

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
def _fit_cubic(W, r0, r1, r2, r3, x1, x2, x3):
    """``R_Q``: the cubic in ``sigma`` through the rows ``r0 .. r3`` at ``sigma = 0, x1, x2, x3``.

    Newton's divided differences, then the monomial coefficients: with
    ``p = a0 + a1 s + a2 s (s - x1) + a3 s (s - x1) (s - x2)``, ``Q_1 = a1 - x1 a2 + x1 x2 a3``,
    ``Q_2 = a2 - (x1 + x2) a3``, ``Q_3 = a3``.
    """
    for m in range(W.shape[1]):
        g0 = W[r0, m]
        d01 = (W[r1, m] - g0) / x1
        d12 = (W[r2, m] - W[r1, m]) / (x2 - x1)
        d23 = (W[r3, m] - W[r2, m]) / (x3 - x2)
        d012 = (d12 - d01) / x2
        d123 = (d23 - d12) / (x3 - x1)
        a3 = (d123 - d012) / x3
        W[E.R_Q, m] = g0
        W[E.R_Q + 1, m] = d01 - x1 * d012 + x1 * x2 * a3
        W[E.R_Q + 2, m] = d012 - (x1 + x2) * a3
        W[E.R_Q + 3, m] = a3


@jitable
def _push(W, fst, row, t):
    """The load in ``row`` at ``t`` becomes the newest of the history."""
    for m in range(W.shape[1]):
        W[R_HIST + 2, m] = W[R_HIST + 1, m]
        W[R_HIST + 1, m] = W[R_HIST, m]
        W[R_HIST, m] = W[row, m]
    fst[F_THIST + 2] = fst[F_THIST + 1]
    fst[F_THIST + 1] = fst[F_THIST]
    fst[F_THIST] = t
    fst[F_NHIST] = min(fst[F_NHIST] + 1.0, 3.0)


@kernel
def step(rhs, p, W, fst, ist):
    """One accepted step: the Runge-Kutta method's while the history fills, then the PECE pair."""
    n = W.shape[1]
    if fst[F_NHIST] < 3.0:
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
            E._tables(W, h, 1.0, R_ATABLE, 5)
            fst[F_AHOLD] = h
        s1 = (fst[F_THIST] - t) / h
        s2 = (fst[F_THIST + 1] - t) / h
        s3 = (fst[F_THIST + 2] - t) / h
        _fit_cubic(W, E.R_G, R_HIST, R_HIST + 1, R_HIST + 2, s1, s2, s3)  # predictor
        E._cubic_solution(W, h, R_ATABLE, R_Y, 1.0, R_YPRED)
        rhs(t_new, W[R_YPRED], W[E.R_FU], p)
        ist[S_NFEV] += 1
        E._load(W, R_YPRED, E.R_FU, E.R_GNEW)
        _fit_cubic(W, E.R_G, E.R_GNEW, R_HIST, R_HIST + 1, 1.0, s1, s2)  # corrector
        E._cubic_solution(W, h, R_ATABLE, R_Y, 1.0, E.R_YNEW)
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
    E.accept(W, fst, ist, t, t_new, h_abs)
    return True
